// The romp command line: one entry point for every mode, with distinct exit codes for bad
// arguments (2) and failed runs (1).
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <exception>
#include <string>

#include "host/backend_selection.h"
#include "host/build_info.h"
#include "host/demo.h"
#include "host/material_library.h"
#include "host/info_report.h"
#include "kernels/core/device.h"
#include "kernels/core/error.h"
#include "nn/torch_info.h"

namespace {

constexpr int kExitRunFailed = 1;
constexpr int kExitBadArguments = 2;

romp::NclawMaterial parse_material(const std::string& name) {
  if (name == "jelly") return romp::NclawMaterial::Jelly;
  if (name == "sand") return romp::NclawMaterial::Sand;
  if (name == "plasticine") return romp::NclawMaterial::Plasticine;
  if (name == "water") return romp::NclawMaterial::Water;
  throw romp::Error("--material '" + name + "': allowed values are jelly, sand, plasticine, water");
}

int run_demo(romp::DeviceChoice choice, int threads, const std::string& material, int steps) {
  const romp::Exec exec = romp::select_backend(choice, threads);
  const romp::DemoResult r = romp::run_cube_demo(exec, parse_material(material), steps);
  fmt::print("{} cube: {} particles, {} substeps ({:.3f} s simulated) in {:.3f} s on {}: {:.3e} particle-substeps/s\n",
             material, r.particles, r.substeps, r.simulated_seconds, r.wall_seconds, romp::to_string(exec.backend),
             double(r.particles) * double(r.substeps) / r.wall_seconds);
  fmt::print("final centre of mass ({:.4f}, {:.4f}, {:.4f}) m, kinetic energy {:.4g} J\n\n{}", r.center_of_mass[0],
             r.center_of_mass[1], r.center_of_mass[2], r.kinetic_energy, romp::stage_table(r.stage_seconds));
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

  CLI::App* demo = app.add_subcommand("demo", "The neural-constitutive-law paper's thrown cube, full-order MPM");
  std::string material = "jelly";
  int steps = 1000;
  demo->add_option("--material", material, "jelly, sand, plasticine or water")
      ->check(CLI::IsMember({"jelly", "sand", "plasticine", "water"}));
  demo->add_option("--steps", steps, "Substeps of 5e-4 s")->check(CLI::PositiveNumber);

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
    return run_demo(choice, threads, material, steps);
  } catch (const std::exception& error) {
    spdlog::error("{}", error.what());
    return kExitRunFailed;
  }
}
