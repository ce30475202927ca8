// The options every romp command takes, before the command's name: the backend, CPU threads and log level.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace romp::cli {

struct GlobalOptions {
  std::string device = "auto";  // auto (CUDA if a device answers), cpu or cuda
  int threads = 0;              // CPU threads; 0: OpenMP's default
  std::string log_level = "info";
};

// Declares the global options on the top-level `app`.
inline void add_global_options(CLI::App& app, GlobalOptions& options) {
  app.add_option("--device", options.device, "Backend: auto (CUDA if a device answers), cpu or cuda")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  app.add_option("--threads", options.threads, "CPU threads (0 = OpenMP default)")->check(CLI::NonNegativeNumber);
  app.add_option("--log-level", options.log_level, "trace, debug, info, warn, error")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error"}));
}

}  // namespace romp::cli
