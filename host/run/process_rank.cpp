// Rank detection from launcher environment variables.
#include "host/run/process_rank.h"

#include <fmt/format.h>

#include <cstdlib>

#include "kernels/core/error.h"

namespace romp::run {
namespace {

int parse_count(const std::string& name, const std::string& text) {
  char* end = nullptr;
  const long value = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || value < 0 || value > 1 << 24)
    throw Error(fmt::format("environment variable {}='{}' is not a valid process count or rank", name, text));
  return int(value);
}

}  // namespace

ProcessRank detect_process_rank(const std::map<std::string, std::string>& environment) {
  static const struct {
    const char* rank;
    const char* size;
    const char* launcher;
  } kLaunchers[] = {{"OMPI_COMM_WORLD_RANK", "OMPI_COMM_WORLD_SIZE", "OpenMPI"}, {"PMI_RANK", "PMI_SIZE", "PMI"}};
  for (const auto& l : kLaunchers) {
    const auto rank = environment.find(l.rank), size = environment.find(l.size);
    if (rank == environment.end() || size == environment.end()) continue;
    ProcessRank r{parse_count(l.rank, rank->second), parse_count(l.size, size->second), l.launcher};
    if (r.size < 1 || r.rank >= r.size)
      throw Error(fmt::format("{}: rank {} is not below the process count {}", r.launcher, r.rank, r.size));
    return r;
  }
  return {};
}

ProcessRank detect_process_rank() {
  std::map<std::string, std::string> environment;
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "OMPI_COMM_WORLD_SIZE", "PMI_RANK", "PMI_SIZE"})
    if (const char* value = std::getenv(name)) environment[name] = value;
  return detect_process_rank(environment);
}

}  // namespace romp::run
