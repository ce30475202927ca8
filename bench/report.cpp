// CSV and JSON output of romp-bench, stamped with device, driver, commit, build type and command.
#include "bench/report.h"

#include <fmt/format.h>
#include <omp.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "host/build_info.h"
#include "kernels/core/device.h"
#include "kernels/core/error.h"

namespace romp::bench {
namespace {

void write_atomically(const std::filesystem::path& path, const std::string& text) {
  const std::filesystem::path temporary = path.string() + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary);
    ROMP_CHECK(out.good(), "cannot write " + temporary.string());
    out << text;
    ROMP_CHECK(out.good(), "failed writing " + temporary.string());
  }
  std::filesystem::rename(temporary, path);
}

nlohmann::json environment(const Context& context) {
  const BuildInfo& build = build_info();
  const CudaProbe cuda = probe_cuda();
  nlohmann::json devices = nlohmann::json::array();
  for (const CudaDevice& device : cuda.devices) {
    devices.push_back({{"ordinal", device.ordinal},
                       {"name", device.name},
                       {"compute_capability", fmt::format("{}.{}", device.compute_major, device.compute_minor)},
                       {"multiprocessors", device.multiprocessors},
                       {"memory_bytes", device.global_memory_bytes}});
  }
  return {{"romp_version", build.version},
          {"commit", build.commit},
          {"build_type", build.build_type},
          {"cxx_compiler", build.cxx_compiler},
          {"cuda_compiled", build.cuda},
          {"cuda_architectures", build.cuda_architectures},
          {"cuda_driver_version", cuda.driver_version},
          {"cuda_runtime_version", cuda.runtime_version},
          {"cuda_devices", devices},
          {"cpu_max_threads", omp_get_max_threads()},
          {"command", context.command_line()},
          {"warmup", context.options().warmup},
          {"repeats", context.options().repeats},
          {"scale", context.options().scale}};
}

}  // namespace

void write_report(const Context& context, const std::string& directory, const std::string& stem) {
  std::filesystem::create_directories(directory);
  const std::filesystem::path base = std::filesystem::path(directory) / stem;

  std::string csv = "suite,name,backend,threads,items,unit,median_s,min_s,max_s,items_per_s,gb_per_s,note\n";
  nlohmann::json rows = nlohmann::json::array();
  for (const Measurement& m : context.measurements()) {
    const double gbps = m.bytes_per_item > 0 ? m.gigabytes_per_second() : 0.0;
    csv += fmt::format("{},{},{},{},{},{},{:.6e},{:.6e},{:.6e},{:.6e},{:.4f},\"{}\"\n", m.suite, m.name, m.backend,
                       m.threads, m.items, m.unit, m.median_seconds(), m.min_seconds(), m.max_seconds(),
                       m.items_per_second(), gbps, m.note);
    rows.push_back({{"suite", m.suite},
                    {"name", m.name},
                    {"backend", m.backend},
                    {"threads", m.threads},
                    {"items", m.items},
                    {"unit", m.unit},
                    {"seconds", m.seconds},
                    {"median_s", m.median_seconds()},
                    {"items_per_s", m.items_per_second()},
                    {"gb_per_s", gbps},
                    {"note", m.note}});
  }
  nlohmann::json records = nlohmann::json::object();
  for (const auto& [key, value] : context.records()) records[key] = value;

  const nlohmann::json document{{"environment", environment(context)}, {"measurements", rows}, {"records", records}};
  write_atomically(base.string() + ".csv", csv);
  write_atomically(base.string() + ".json", document.dump(2) + "\n");
}

}  // namespace romp::bench
