// The stage table printed at the end of a run: seconds and share of each stage that ran.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace romp::run {

std::string stage_table(const std::vector<std::pair<std::string, double>>& stage_seconds);

}  // namespace romp::run
