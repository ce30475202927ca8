// TableReader: schema-checked reads of TOML tables with located errors and a resolved copy.
#include "host/scene/toml_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "kernels/core/error.h"

namespace romp::scene {
namespace {

std::string quoted_list(const std::vector<std::string>& names) {
  std::string list;
  for (const std::string& name : names) list += (list.empty() ? "" : ", ") + ("\"" + name + "\"");
  return list;
}

const char* type_name(const toml::node& node) {
  if (node.is_table()) return "a table";
  if (node.is_array()) return "an array";
  if (node.is_boolean()) return "a boolean";
  if (node.is_date() || node.is_time() || node.is_date_time()) return "a date or time";
  return "a value of another type";
}

std::string number_text(double value) { return fmt::format("{:.10g}", value); }

}  // namespace

bool Range::contains(double value) const {
  const bool above = low_open ? value > low : value >= low;
  const bool below = high_open ? value < high : value <= high;
  return above && below;
}

std::string Range::describe() const {
  const bool unbounded_low = low <= -1e300, unbounded_high = high >= 1e300;
  if (unbounded_low && unbounded_high) return "any finite number";
  if (unbounded_high) return fmt::format("{} {}", low_open ? ">" : ">=", number_text(low));
  if (unbounded_low) return fmt::format("{} {}", high_open ? "<" : "<=", number_text(high));
  return fmt::format("in {}{}, {}{}", low_open ? "(" : "[", number_text(low), number_text(high), high_open ? ")" : "]");
}

TableReader::TableReader(const toml::table& in, toml::table& out, std::string path, const ReadContext& context)
    : in_(in), out_(&out), path_(std::move(path)), context_(&context) {}

std::string TableReader::where(const toml::source_region& source) const {
  if (source.begin.line == 0) return context_->file;
  return fmt::format("{}:{}:{}", context_->file, source.begin.line, source.begin.column);
}

std::string TableReader::dotted(const std::string& key) const {
  if (key.empty()) return path_.empty() ? "(top level)" : path_;
  return path_.empty() ? key : path_ + "." + key;
}

std::string TableReader::located(const std::string& key) const {
  const toml::node* node = key.empty() ? nullptr : in_.get(key);
  const toml::source_region& source = node ? node->source() : in_.source();
  return fmt::format("{}: {}", where(source), dotted(key));
}

void TableReader::fail(const std::string& key, const std::string& why) const {
  throw SceneError(fmt::format("{}: {}", located(key), why));
}

const toml::node* TableReader::find(const std::string& key) {
  read_.insert(key);
  return in_.get(key);
}

double TableReader::to_number(const std::string& key, const toml::node& node) const {
  double value = 0.0;
  if (const auto* integer = node.as_integer()) {
    value = double(integer->get());
  } else if (const auto* floating = node.as_floating_point()) {
    value = floating->get();
  } else if (const auto* formula = node.as_string()) {
    try {
      value = evaluate_expression(formula->get(), context_->parameters);
    } catch (const Error& error) {
      fail(key, error.what());
    }
  } else {
    fail(key, fmt::format("expected a number or a formula string, got {}", type_name(node)));
  }
  if (!std::isfinite(value)) fail(key, fmt::format("must be finite, got {}", value));
  return value;
}

double TableReader::number(const std::string& key, double fallback, const Range& range) {
  const toml::node* node = find(key);
  const double value = node ? to_number(key, *node) : fallback;
  if (!range.contains(value)) fail(key, fmt::format("must be {}, got {}", range.describe(), number_text(value)));
  out_->insert_or_assign(key, value);
  return value;
}

double TableReader::required_number(const std::string& key, const Range& range) {
  if (!has(key)) fail("", fmt::format("missing required key '{}' (a number {})", key, range.describe()));
  return number(key, 0.0, range);
}

std::int64_t TableReader::integer(const std::string& key, std::int64_t fallback, const Range& range) {
  const toml::node* node = find(key);
  double value = double(fallback);
  if (node) {
    value = to_number(key, *node);
    if (value != std::floor(value) || std::fabs(value) > 9e15)
      fail(key, fmt::format("must be a whole number, got {}", number_text(value)));
  }
  if (!range.contains(value)) fail(key, fmt::format("must be {}, got {}", range.describe(), number_text(value)));
  out_->insert_or_assign(key, std::int64_t(value));
  return std::int64_t(value);
}

std::vector<double> TableReader::numbers(const std::string& key, const std::vector<double>& fallback,
                                         const Range& range, std::size_t min_count, std::size_t max_count) {
  const toml::node* node = find(key);
  std::vector<double> values = fallback;
  if (node) {
    const toml::array* array = node->as_array();
    const std::string expected =
        min_count == max_count ? fmt::format("{}", min_count) : fmt::format("{} to {}", min_count, max_count);
    if (!array || array->size() < min_count || array->size() > max_count)
      fail(key, fmt::format("expected an array of {} numbers", expected));
    values.clear();
    for (const toml::node& element : *array) {
      const double value = to_number(key, element);
      if (!range.contains(value))
        fail(key, fmt::format("every entry must be {}, got {}", range.describe(), number_text(value)));
      values.push_back(value);
    }
  }
  toml::array resolved;
  for (const double value : values) resolved.push_back(value);
  out_->insert_or_assign(key, std::move(resolved));
  return values;
}

std::vector<double> TableReader::required_numbers(const std::string& key, const Range& range, std::size_t min_count,
                                                  std::size_t max_count) {
  if (!has(key)) fail("", fmt::format("missing required key '{}' (an array of numbers)", key));
  return numbers(key, {}, range, min_count, max_count);
}

Vec3<double> TableReader::vec3(const std::string& key, const Vec3<double>& fallback) {
  const std::vector<double> v = numbers(key, {fallback[0], fallback[1], fallback[2]}, Range::any(), 3, 3);
  return Vec3<double>(v[0], v[1], v[2]);
}

TableReader::VectorField TableReader::vec3_field(const std::string& key, const std::vector<std::string>& variables) {
  VectorField field;
  const toml::node* node = find(key);
  toml::array resolved;
  if (!node) {
    for (int a = 0; a < 3; ++a) resolved.push_back(0.0);
    out_->insert_or_assign(key, std::move(resolved));
    return field;
  }
  const toml::array* array = node->as_array();
  if (!array || array->size() != 3) fail(key, "expected an array of 3 numbers or formulas");
  for (int a = 0; a < 3; ++a) {
    const toml::node& element = *array->get(std::size_t(a));
    const auto* text = element.as_string();
    if (!text) {
      field.constant[a] = to_number(key, element);
      resolved.push_back(field.constant[a]);
      continue;
    }
    std::optional<Formula> formula;
    try {
      formula.emplace(text->get(), context_->parameters, variables);
    } catch (const Error& error) {
      fail(key, error.what());
    }
    if (formula->uses_variables()) {
      field.formulas[std::size_t(a)] = text->get();
      resolved.push_back(text->get());
      continue;
    }
    field.constant[a] = (*formula)({});
    if (!std::isfinite(field.constant[a])) fail(key, fmt::format("must be finite, got {}", field.constant[a]));
    resolved.push_back(field.constant[a]);
  }
  out_->insert_or_assign(key, std::move(resolved));
  return field;
}

Vec3<double> TableReader::required_vec3(const std::string& key) {
  if (!has(key)) fail("", fmt::format("missing required key '{}' (an array of 3 numbers)", key));
  return vec3(key, Vec3<double>::zero());
}

bool TableReader::boolean(const std::string& key, bool fallback) {
  const toml::node* node = find(key);
  bool value = fallback;
  if (node) {
    const auto* flag = node->as_boolean();
    if (!flag) fail(key, "expected true or false");
    value = flag->get();
  }
  out_->insert_or_assign(key, value);
  return value;
}

std::string TableReader::string(const std::string& key, const std::string& fallback) {
  const toml::node* node = find(key);
  std::string value = fallback;
  if (node) {
    const auto* text = node->as_string();
    if (!text) fail(key, "expected a string");
    value = text->get();
  }
  out_->insert_or_assign(key, value);
  return value;
}

std::string TableReader::required_string(const std::string& key) {
  if (!has(key)) fail("", fmt::format("missing required key '{}' (a string)", key));
  return string(key, "");
}

std::string TableReader::choice(const std::string& key, const std::string& fallback,
                                const std::vector<std::string>& allowed) {
  const std::string value = string(key, fallback);
  if (std::find(allowed.begin(), allowed.end(), value) == allowed.end())
    fail(key, fmt::format("\"{}\" is not one of {}", value, quoted_list(allowed)));
  return value;
}

std::string TableReader::required_choice(const std::string& key, const std::vector<std::string>& allowed) {
  if (!has(key)) fail("", fmt::format("missing required key '{}' (one of {})", key, quoted_list(allowed)));
  return choice(key, "", allowed);
}

std::vector<std::string> TableReader::choices(const std::string& key, const std::vector<std::string>& fallback,
                                              const std::vector<std::string>& allowed) {
  const toml::node* node = find(key);
  std::vector<std::string> values = fallback;
  if (node) {
    const toml::array* array = node->as_array();
    if (!array) fail(key, fmt::format("expected an array of strings from {}", quoted_list(allowed)));
    values.clear();
    for (const toml::node& element : *array) {
      const auto* text = element.as_string();
      if (!text) fail(key, fmt::format("expected an array of strings from {}", quoted_list(allowed)));
      if (std::find(allowed.begin(), allowed.end(), text->get()) == allowed.end())
        fail(key, fmt::format("\"{}\" is not one of {}", text->get(), quoted_list(allowed)));
      if (std::find(values.begin(), values.end(), text->get()) != values.end())
        fail(key, fmt::format("\"{}\" is listed twice", text->get()));
      values.push_back(text->get());
    }
  }
  toml::array resolved;
  for (const std::string& value : values) resolved.push_back(value);
  out_->insert_or_assign(key, std::move(resolved));
  return values;
}

TableReader TableReader::table(const std::string& key) {
  if (!has(key)) fail("", fmt::format("missing required table '{}'", key));
  return optional_table(key);
}

TableReader TableReader::optional_table(const std::string& key) {
  static const toml::table kEmpty;
  const toml::node* node = find(key);
  if (node && !node->is_table()) fail(key, "expected a table");
  auto [slot, inserted] = out_->insert_or_assign(key, toml::table{});
  return TableReader(node ? *node->as_table() : kEmpty, *slot->second.as_table(), dotted(key), *context_);
}

std::vector<TableReader> TableReader::tables(const std::string& key) {
  const toml::node* node = find(key);
  std::vector<TableReader> readers;
  auto [slot, inserted] = out_->insert_or_assign(key, toml::array{});
  if (!node) return readers;
  const toml::array* array = node->as_array();
  if (!array || (!array->empty() && !array->is_array_of_tables()))
    fail(key, fmt::format("expected an array of tables, written [[{}]]", dotted(key)));
  toml::array& resolved = *slot->second.as_array();
  for (std::size_t i = 0; i < array->size(); ++i) resolved.push_back(toml::table{});
  for (std::size_t i = 0; i < array->size(); ++i)
    readers.emplace_back(*array->get(i)->as_table(), *resolved.get(i)->as_table(),
                         fmt::format("{}[{}]", dotted(key), i), *context_);
  return readers;
}

std::vector<std::string> TableReader::keys() const {
  std::vector<std::string> names;
  for (const auto& [key, node] : in_) names.emplace_back(key.str());
  return names;
}

void TableReader::finish() const {
  for (const auto& [key, node] : in_) {
    const std::string name(key.str());
    if (read_.count(name) != 0) continue;
    std::string list;
    for (const std::string& a : read_) list += (list.empty() ? "" : ", ") + a;
    throw SceneError(fmt::format("{}: {}: unknown key '{}'; allowed here: {}", where(key.source()), dotted(""), name,
                                 list.empty() ? "none" : list));
  }
}

namespace {

bool is_ascii(char c) { return static_cast<unsigned char>(c) < 0x80; }

// The byte offset of the first non-ASCII character toml++ could test for Unicode whitespace, or npos. That
// test in toml++ 3.3 (Debian 12's libtomlplusplus) reaches __builtin_unreachable for most code points below
// U+049A (é, ×, μ, ν) and in U+2CEE-U+30E7 and U+FB46-U+FEFE: undefined behaviour (toml++ issues #190, #295).
// It asks outside strings and comments, where TOML allows no non-ASCII character, also while it looks ahead
// over a bare value (quotes there start no string), and in a multi-line basic string after a backslash, where
// only a line-ending backslash may precede one. So this follows where toml++ starts a string: where a key
// or a value begins.
std::size_t whitespace_test_toml_cannot_take(const std::string& text) {
  enum class In { Toml, Comment, Basic, Literal, MultiLineBasic, MultiLineLiteral } in = In::Toml;
  // What comes next outside strings: a key, a value, the rest of a key (a '.' asks for another part), a bare
  // value (a number, date or boolean, which toml++ scans to its end, quotes included), or what follows a value.
  enum class Expect { Key, Value, RestOfKey, BareValue, RestOfValue } expect = Expect::Key;
  Expect after_string = Expect::RestOfKey;
  std::vector<char> open;  // the arrays '[' and inline tables '{' around the place
  const std::size_t size = text.size();
  // The end of a run of quotes at `at` of at most 5 (toml++'s lookahead): 3 or more close a multi-line string.
  const auto quote_run = [&](std::size_t at, char quote) {
    std::size_t end = at;
    while (end < size && end - at < 5 && text[end] == quote) ++end;
    return end;
  };
  // A UTF-8 byte order mark is read before the document.
  for (std::size_t i = text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0; i < size; ++i) {
    const char c = text[i];
    switch (in) {
      case In::Toml: {
        if (!is_ascii(c)) return i;
        const bool blank = c == ' ' || c == '\t' || c == '\r' || c == '\n';
        if (expect == Expect::BareValue) {
          if (!blank && c != ']' && c != '}' && c != ',' && c != '#') break;
          expect = Expect::RestOfValue;
        }
        if (c == '#') {
          in = In::Comment;
        } else if ((c == '"' || c == '\'') && (expect == Expect::Key || expect == Expect::Value)) {
          const bool multi_line = text.compare(i, 3, std::string(3, c)) == 0;
          in = c == '"' ? (multi_line ? In::MultiLineBasic : In::Basic)
                        : (multi_line ? In::MultiLineLiteral : In::Literal);
          if (multi_line) i += 2;
          after_string = expect == Expect::Key ? Expect::RestOfKey : Expect::RestOfValue;
        } else if (c == '\n') {
          if (open.empty()) expect = Expect::Key;
        } else if (c == '=') {
          expect = Expect::Value;
        } else if ((c == '[' || c == '{') && expect == Expect::Value) {
          open.push_back(c);
          expect = c == '[' ? Expect::Value : Expect::Key;
        } else if (c == '[') {
          expect = Expect::Key;  // a table header (toml++ stops at one anywhere else)
        } else if (c == ']' || c == '}') {
          if (!open.empty()) open.pop_back();
          expect = Expect::RestOfValue;
        } else if (c == ',') {
          expect = !open.empty() && open.back() == '{' ? Expect::Key : Expect::Value;
        } else if (c == '.' && expect == Expect::RestOfKey) {
          expect = Expect::Key;
        } else if (!blank) {
          expect = expect == Expect::Key || expect == Expect::RestOfKey ? Expect::RestOfKey : Expect::BareValue;
        }
        break;
      }
      case In::Comment:
        if (c == '\n') {
          in = In::Toml;
          if (open.empty()) expect = Expect::Key;
        }
        break;
      case In::Basic:
        if (c == '\\') {
          ++i;
        } else if (c == '"' || c == '\n') {
          in = In::Toml;
          expect = after_string;
          if (c == '\n' && open.empty()) expect = Expect::Key;
        }
        break;
      case In::Literal:
        if (c == '\'' || c == '\n') {
          in = In::Toml;
          expect = after_string;
          if (c == '\n' && open.empty()) expect = Expect::Key;
        }
        break;
      case In::MultiLineBasic:
      case In::MultiLineLiteral:
        if (c == '\\' && in == In::MultiLineBasic) {
          // The escaped character, or past a line-ending backslash's whitespace the first one kept.
          std::size_t next = i + 1;
          while (next < size && (text[next] == ' ' || text[next] == '\t' || text[next] == '\r' || text[next] == '\n'))
            ++next;
          if (next < size && !is_ascii(text[next])) return next;
          i = next == i + 1 ? next : next - 1;
        } else if (c == (in == In::MultiLineBasic ? '"' : '\'')) {
          const std::size_t end = quote_run(i, c);
          if (end - i >= 3) {
            in = In::Toml;
            expect = after_string;
          }
          i = end - 1;
        }
        break;
    }
  }
  return std::string::npos;
}

}  // namespace

toml::table parse_toml(const std::string& text, const std::string& file) {
  const std::size_t unsafe = whitespace_test_toml_cannot_take(text);
  if (unsafe != std::string::npos) {
    const std::size_t line_start = text.rfind('\n', unsafe) + 1;  // 0 on the first line (npos + 1)
    const auto line = 1 + std::count(text.begin(), text.begin() + std::ptrdiff_t(line_start), '\n');
    // Columns count characters, as toml++'s do: every byte but UTF-8 continuation bytes.
    const auto column =
        1 + std::count_if(text.begin() + std::ptrdiff_t(line_start), text.begin() + std::ptrdiff_t(unsafe),
                          [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; });
    throw SceneError(
        fmt::format("{}:{}:{}: TOML syntax error: a non-ASCII character outside a string or comment, or "
                    "after a backslash in a multi-line string (toml++ cannot read it there)",
                    file, line, column));
  }
  try {
    return toml::parse(text, file);
  } catch (const toml::parse_error& error) {
    throw SceneError(fmt::format("{}:{}:{}: TOML syntax error: {}", file, error.source().begin.line,
                                 error.source().begin.column, error.description()));
  }
}

}  // namespace romp::scene
