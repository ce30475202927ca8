// Stage table formatting.
#include "host/run/stage_table.h"

#include <fmt/format.h>

namespace romp::run {

std::string stage_table(const std::vector<std::pair<std::string, double>>& stage_seconds) {
  double total = 0.0;
  for (const auto& [stage, seconds] : stage_seconds) total += seconds;
  std::string table = fmt::format("{:<14}{:>12}{:>9}\n", "stage", "seconds", "share");
  for (const auto& [stage, seconds] : stage_seconds)
    table += fmt::format("{:<14}{:>12.4f}{:>8.1f}%\n", stage, seconds, total > 0 ? 100.0 * seconds / total : 0.0);
  table += fmt::format("{:<14}{:>12.4f}\n", "total", total);
  return table;
}

}  // namespace romp::run
