// The romp command line: one entry point for every mode, with distinct exit codes for bad
// arguments (2) and failed runs (1).
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <exception>

#include "host/backend_selection.h"
#include "host/build_info.h"
#include "host/demo.h"
#include "host/info_report.h"
#include "kernels/core/device.h"
#include "kernels/core/error.h"
#include "nn/torch_info.h"

namespace {

constexpr int kExitRunFailed = 1;
constexpr int kExitBadArguments = 2;

// Float error of the demo's 1 s flight: positions of O(1) m after `steps` float additions.
constexpr double kDemoTolerance = 1e-4;

int run_demo(romp::DeviceChoice choice, int threads, romp::Index particles, int steps) {
  const romp::Exec exec = romp::select_backend(choice, threads);
  const romp::DemoResult result = romp::run_free_flight_demo(exec, particles, steps);
  fmt::print("free flight: {} particles, {} steps on {}: {:.3e} particle-steps/s, max error {:.2e} m\n",
             result.particles, result.steps, romp::to_string(exec.backend), result.particle_steps_per_second(),
             result.max_position_error);
  if (result.max_position_error > kDemoTolerance) {
    spdlog::error("free flight deviates from the exact solution by {:.2e} m (tolerance {:.0e} m)",
                  result.max_position_error, kDemoTolerance);
    return kExitRunFailed;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"romp: material point method with neural reduced-order models"};
  app.require_subcommand(1);
  std::string device = "auto";
  int threads = 0;
  std::string log_level = "info";
  app.add_option("--device", device, "Backend: auto (CUDA if a device answers), cpu or cuda")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  app.add_option("--threads", threads, "CPU threads (0 = OpenMP default)")->check(CLI::NonNegativeNumber);
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error"}));

  app.add_subcommand("info", "Version, commit, build configuration and the devices found");

  CLI::App* demo = app.add_subcommand("demo", "Free flight of a particle cloud, checked against the exact solution");
  romp::Index particles = 1 << 20;
  int steps = 1000;
  demo->add_option("--particles", particles, "Number of particles")->check(CLI::PositiveNumber);
  demo->add_option("--steps", steps, "Time steps over one simulated second")->check(CLI::PositiveNumber);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    const int code = app.exit(error);
    return code == 0 ? 0 : kExitBadArguments;
  }
  spdlog::set_level(spdlog::level::from_str(log_level));

  try {
    const romp::DeviceChoice choice = romp::parse_device_choice(device);
    if (app.got_subcommand("info")) {
      fmt::print("{}", romp::info_report(romp::build_info(), romp::probe_cuda(), romp::nn::torch_info()));
      return 0;
    }
    return run_demo(choice, threads, particles, steps);
  } catch (const std::exception& error) {
    spdlog::error("{}", error.what());
    return kExitRunFailed;
  }
}
