// romp-bench: runs the requested suites on the CPU (and the GPU when present) and writes CSV + JSON.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <exception>
#include <string>
#include <vector>

#include "bench/harness.h"
#include "bench/report.h"
#include "bench/suites/suites.h"
#include "host/backend_selection.h"
#include "host/scene/expression.h"

namespace {

using romp::bench::Suite;

// Order matters: later suites may read records of earlier ones (svd compares with memory's copy bandwidth).
const std::vector<Suite> kSuites = {
    {"memory", "copy bandwidth of each backend (the bound for memory-bound kernels)", romp::bench::run_memory_suite},
    {"step", "full-order MPM particle-substeps per second and memory per particle", romp::bench::run_step_suite},
    {"svd", "batched 3x3 SVD against Eigen (CPU) and cuSOLVER (GPU); share of copy bandwidth",
     romp::bench::run_svd_suite},
    {"train", "seconds per neural-law training epoch (1000 substeps forward and backward)",
     romp::bench::run_train_suite},
    {"law",
     "one neural constitutive law on 1k and 117k particles, forward and backward: fused kernels against LibTorch",
     romp::bench::run_law_suite},
    {"mlp", "deformation map g, grad g, dg/dxhat at 1k-200k points: fused kernel against LibTorch",
     romp::bench::run_mlp_suite},
    {"quadrature", "reduced substep, Lagrangian quadrature over every point against over the samples' neighbours",
     romp::bench::run_quadrature_suite},
    {"rom", "ROM error against wall time per simulated second, every quadrature x projection (--scene, --rom-model)",
     romp::bench::run_rom_suite},
    {"rom-cost",
     "one substep, full order against every reduced setup, at a scene's resolution with a random map (--scene)",
     romp::bench::run_rom_cost_suite},
    {"stability", "robust-elasticity matrix: each case ends finite with bounded energy or stops with a message",
     romp::bench::run_stability_suite},
};

std::string joined_command(int argc, char** argv) {
  std::string command;
  for (int i = 0; i < argc; ++i) command += (i ? " " : "") + std::string(argv[i]);
  return command;
}

std::string timestamp() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  char text[32];
  std::strftime(text, sizeof text, "%Y%m%d-%H%M%S", std::gmtime(&now));
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"romp-bench: timed suites with medians over repeats, written as CSV and JSON"};
  std::vector<std::string> requested;
  std::string device = "auto";
  std::string out_directory = "romp-bench-results";
  std::string stem;
  romp::bench::Options options;
  std::vector<std::string> suite_names;
  for (const Suite& suite : kSuites) suite_names.push_back(suite.name);

  app.add_option("--suite", requested, "Suites to run (default: all)")->check(CLI::IsMember(suite_names));
  app.add_option("--device", device, "auto (CPU, plus CUDA if a device answers), cpu or cuda")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  app.add_option("--threads", options.cpu_threads, "CPU thread counts to measure")->check(CLI::PositiveNumber);
  app.add_option("--repeats", options.repeats, "Timed repeats; the median is reported")->check(CLI::PositiveNumber);
  app.add_option("--warmup", options.warmup, "Untimed runs before timing")->check(CLI::NonNegativeNumber);
  app.add_option("--scale", options.scale, "Multiplies every problem size")->check(CLI::PositiveNumber);
  app.add_option("--out", out_directory, "Folder for the CSV and JSON records");
  app.add_option("--name", stem, "File stem of the records (default: bench-<UTC time>)");
  std::vector<std::string> sets;
  app.add_option("--scene", options.scene, "rom and rom-cost suites: the scene file")->check(CLI::ExistingFile);
  app.add_option("--set", sets,
                 "rom and rom-cost suites: override a declared scene parameter; stability suite: min_youngs, "
                 "max_youngs, implicit, enriched, substeps, seconds; name=value (repeatable)");
  app.add_option("--rom-model", options.rom_model, "rom suite: a model trained on the scene's sweep (romp train-rom)")
      ->check(CLI::ExistingFile);
  app.add_option("--rom-samples", options.rom_samples,
                 "rom and rom-cost suites: sample counts per substep of the reduced cases (0: every point)")
      ->delimiter(',')
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_flag_callback(
      "--list",
      [] {
    for (const Suite& suite : kSuites) fmt::print("{:<10} {}\n", suite.name, suite.summary);
    throw CLI::Success();
      },
      "List the suites and exit");
  CLI11_PARSE(app, argc, argv);

  try {
    options.parameters = romp::scene::parse_assignments(sets);
    const romp::DeviceChoice choice = romp::parse_device_choice(device);
    const romp::Exec exec = romp::select_backend(choice);
    options.use_cuda = exec.is_cuda();
    options.cuda_device = exec.device;
    if (choice == romp::DeviceChoice::Cuda) options.cpu_threads.clear();

    romp::bench::Context context(options, joined_command(argc, argv));
    std::vector<const Suite*> chosen;
    for (const Suite& suite : kSuites)
      if (requested.empty() || std::find(requested.begin(), requested.end(), suite.name) != requested.end())
        chosen.push_back(&suite);
    // Progress: which suite of how many, and the time so far (suites take seconds to an hour).
    const auto started = std::chrono::steady_clock::now();
    for (std::size_t k = 0; k < chosen.size(); ++k) {
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
      fmt::print(stderr, "romp-bench: suite {}/{}: {} ({:.0f} s so far)\n", k + 1, chosen.size(), chosen[k]->name,
                 elapsed);
      chosen[k]->run(context);
    }
    if (stem.empty()) stem = "bench-" + timestamp();
    romp::bench::write_report(context, out_directory, stem);
    fmt::print("wrote {}/{}.csv and .json\n", out_directory, stem);
    return 0;
  } catch (const std::exception& error) {
    fmt::print(stderr, "romp-bench: {}\n", error.what());
    return 1;
  }
}
