// What a romp file that logs and links Torch includes (host/reduced_sim.cpp, for one).
#include <torch/torch.h>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <vector>

void log_sizes(const std::vector<int>& sizes) { spdlog::info("sizes {}", fmt::join(sizes, ", ")); }
