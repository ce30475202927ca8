// The resolved-scene printer.
#include "host/scene/toml_writer.h"

#include <fmt/format.h>

#include <algorithm>

namespace romp::scene {
namespace {

bool is_array_of_tables(const toml::node& node) {
  const toml::array* array = node.as_array();
  return array && !array->empty() && array->is_array_of_tables();
}

bool is_simple(const toml::node& node) { return !node.is_table() && !is_array_of_tables(node); }

std::string key_text(const std::string& key) {
  const bool bare = !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
  });
  if (bare) return key;
  std::string quoted = "\"";
  for (char c : key) quoted += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
  return quoted + "\"";
}

std::string string_text(const std::string& text) {
  std::string out = "\"";
  for (unsigned char c : text) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default: out += c < 0x20 || c == 0x7f ? fmt::format("\\u{:04X}", c) : std::string(1, char(c));
    }
  }
  return out + "\"";
}

std::string value_text(const toml::node& node) {
  if (const auto* s = node.as_string()) return string_text(s->get());
  if (const auto* i = node.as_integer()) return fmt::format("{}", i->get());
  if (const auto* b = node.as_boolean()) return b->get() ? "true" : "false";
  if (const auto* f = node.as_floating_point()) {
    std::string text = fmt::format("{}", f->get());  // shortest text that reads back to the same double
    if (text.find_first_of(".eEn") == std::string::npos) text += ".0";
    return text;
  }
  if (const auto* a = node.as_array()) {
    std::string text = "[";
    for (std::size_t i = 0; i < a->size(); ++i) text += (i ? ", " : "") + value_text(*a->get(i));
    return text + "]";
  }
  return "\"\"";  // dates and times never occur in a resolved scene
}

std::vector<std::string> ordered_keys(const toml::table& table, const std::vector<std::string>& first) {
  std::vector<std::string> keys;
  for (const std::string& key : first)
    if (table.contains(key)) keys.push_back(key);
  // `first` is a handful of names: the rest are checked against it, not against every key so far, so a
  // table of many keys (100,000 parameters) is written in linear time.
  for (const auto& [key, node] : table)
    if (std::find(first.begin(), first.end(), std::string(key.str())) == first.end()) keys.emplace_back(key.str());
  return keys;
}

void write_table(std::string& out, const toml::table& table, const std::string& path,
                 const std::vector<std::string>& order) {
  // Within a table, its identity comes first: the type or name that decides which keys apply.
  const std::vector<std::string> keys =
      ordered_keys(table, order.empty() ? std::vector<std::string>{"type", "name"} : order);
  for (const std::string& key : keys)
    if (is_simple(*table.get(key))) out += fmt::format("{} = {}\n", key_text(key), value_text(*table.get(key)));
  for (const std::string& key : keys) {
    const toml::node& node = *table.get(key);
    const std::string child = path.empty() ? key_text(key) : path + "." + key_text(key);
    if (const toml::table* sub = node.as_table()) {
      out += fmt::format("\n[{}]\n", child);
      write_table(out, *sub, child, {});
    } else if (is_array_of_tables(node)) {
      for (const toml::node& element : *node.as_array()) {
        out += fmt::format("\n[[{}]]\n", child);
        write_table(out, *element.as_table(), child, {});
      }
    }
  }
}

}  // namespace

std::string to_toml(const toml::table& table, const std::vector<std::string>& top_order) {
  std::string out;
  write_table(out, table, "", top_order);
  return out;
}

}  // namespace romp::scene
