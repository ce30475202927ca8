// Stage table formatting.
#include "host/run/stage_table.h"

#include <fmt/format.h>

#include <algorithm>

namespace romp::run {

std::string stage_table(const std::vector<std::pair<std::string, double>>& stage_seconds) {
  double total = 0.0;
  std::size_t width = 14;  // the name column: at least this, and as wide as the longest stage name
  for (const auto& [stage, seconds] : stage_seconds) {
    total += seconds;
    width = std::max(width, stage.size() + 1);
  }
  std::string table = fmt::format("{:<{}}{:>12}{:>9}\n", "stage", width, "seconds", "share");
  for (const auto& [stage, seconds] : stage_seconds)
    table +=
        fmt::format("{:<{}}{:>12.4f}{:>8.1f}%\n", stage, width, seconds, total > 0 ? 100.0 * seconds / total : 0.0);
  table += fmt::format("{:<{}}{:>12.4f}\n", "total", width, total);
  return table;
}

}  // namespace romp::run
