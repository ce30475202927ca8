// TableReader: reads one TOML table against a schema, so every scene error names the file, line,
// key and allowed range, unknown keys are rejected, and the resolved scene (every default filled in,
// every formula evaluated) is recorded as it is read.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "host/scene/expression.h"
#include "kernels/core/error.h"
#include "kernels/math/vec3.h"

namespace romp::scene {

// A scene file that cannot be used as written (syntax, unknown key, value out of range, missing
// file it names): the user's input is wrong, not the run.
class SceneError : public Error {
 public:
  using Error::Error;
};

// An interval of allowed values, printed in errors ("in (0, 1]").
struct Range {
  double low = -1e300, high = 1e300;
  bool low_open = false, high_open = false;

  static Range any() { return {}; }
  static Range positive() { return {0.0, 1e300, true, false}; }
  static Range non_negative() { return {0.0, 1e300, false, false}; }
  static Range closed(double low, double high) { return {low, high, false, false}; }
  static Range open_closed(double low, double high) { return {low, high, true, false}; }
  static Range closed_open(double low, double high) { return {low, high, false, true}; }
  bool contains(double value) const;
  std::string describe() const;
};

// What every reader of one file shares: the file name for messages and the parameters formulas see.
struct ReadContext {
  std::string file;
  ParameterValues parameters;
};

class TableReader {
 public:
  // Reads `in`, whose dotted path in the scene is `path` ("" for the root), recording the resolved
  // values in `out`.
  TableReader(const toml::table& in, toml::table& out, std::string path, const ReadContext& context);

  bool has(const std::string& key) const { return in_.contains(key); }

  // A number (TOML integer or float, or a string formula over the parameters) in `range`.
  double number(const std::string& key, double fallback, const Range& range);
  double required_number(const std::string& key, const Range& range);
  std::int64_t integer(const std::string& key, std::int64_t fallback, const Range& range);
  // An array of numbers, each in `range`, with between `min_count` and `max_count` entries.
  std::vector<double> numbers(const std::string& key, const std::vector<double>& fallback, const Range& range,
                              std::size_t min_count, std::size_t max_count);
  std::vector<double> required_numbers(const std::string& key, const Range& range, std::size_t min_count,
                                       std::size_t max_count);
  Vec3<double> vec3(const std::string& key, const Vec3<double>& fallback);
  // A vector field: 3 entries, each a number, a formula of the parameters, or a formula that also uses
  // `variables` (e.g. x, y, z). Entries that use no variable are evaluated into `constant` (0 where a
  // formula is kept); those that do are compiled here (so that their errors name the key) and returned
  // as text in `formulas` (empty for a constant entry), to be evaluated by the caller. Absent: zero.
  struct VectorField {
    Vec3<double> constant = Vec3<double>::zero();
    std::array<std::string, 3> formulas;
    bool varies() const { return !formulas[0].empty() || !formulas[1].empty() || !formulas[2].empty(); }
  };
  VectorField vec3_field(const std::string& key, const std::vector<std::string>& variables);
  Vec3<double> required_vec3(const std::string& key);
  bool boolean(const std::string& key, bool fallback);
  std::string string(const std::string& key, const std::string& fallback);
  std::string required_string(const std::string& key);
  // One of `allowed`.
  std::string choice(const std::string& key, const std::string& fallback, const std::vector<std::string>& allowed);
  std::string required_choice(const std::string& key, const std::vector<std::string>& allowed);
  // A list of distinct strings, each one of `allowed`.
  std::vector<std::string> choices(const std::string& key, const std::vector<std::string>& fallback,
                                   const std::vector<std::string>& allowed);

  // Sub-tables: required, optional (an empty table when absent), and arrays of tables.
  TableReader table(const std::string& key);
  TableReader optional_table(const std::string& key);
  std::vector<TableReader> tables(const std::string& key);
  // The keys of a table whose keys are names the user chooses (e.g. [materials.<name>]).
  std::vector<std::string> keys() const;

  // Records `value` as what `key` resolved to, in place of the text read: a file name made absolute,
  // so that the resolved scene (stored in outputs, written for sweep members) reads the same from
  // any folder.
  void resolve_as(const std::string& key, const std::string& value) { out_->insert_or_assign(key, value); }

  // Throws if the table holds a key no read asked for, listing the keys allowed here.
  void finish() const;

  // Throws romp::Error "file:line:column: path.key: why" at `key` (or at the table when absent).
  [[noreturn]] void fail(const std::string& key, const std::string& why) const;
  // "file:line:column: path.key", the place fail() names: for an error found later, outside the parser.
  std::string located(const std::string& key) const;

  const std::string& path() const { return path_; }
  const ReadContext& context() const { return *context_; }

 private:
  const toml::node* find(const std::string& key);
  double to_number(const std::string& key, const toml::node& node) const;
  std::string where(const toml::source_region& source) const;
  std::string dotted(const std::string& key) const;

  const toml::table& in_;
  toml::table* out_;
  std::string path_;
  const ReadContext* context_;
  std::set<std::string> read_;  // the keys asked for (a set: a table of many keys reads in n log n)
};

// Parses TOML text; a syntax error becomes romp::Error "file:line:column: why".
toml::table parse_toml(const std::string& text, const std::string& file);

}  // namespace romp::scene
