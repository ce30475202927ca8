// Timing loop and statistics of romp-bench.
#include "bench/harness.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "kernels/core/device_timer.h"
#include "kernels/core/error.h"

namespace romp::bench {
namespace {

std::vector<double> sorted(std::vector<double> values) {
  ROMP_CHECK(!values.empty(), "a measurement needs at least one timed repeat");
  std::sort(values.begin(), values.end());
  return values;
}

}  // namespace

double Measurement::median_seconds() const {
  const std::vector<double> s = sorted(seconds);
  const std::size_t n = s.size();
  return n % 2 == 1 ? s[n / 2] : 0.5 * (s[n / 2 - 1] + s[n / 2]);
}
double Measurement::min_seconds() const { return sorted(seconds).front(); }
double Measurement::max_seconds() const { return sorted(seconds).back(); }

Context::Context(Options options, std::string command_line)
    : options_(std::move(options)), command_line_(std::move(command_line)) {
  ROMP_CHECK(options_.repeats >= 1, "--repeats must be >= 1, got " + std::to_string(options_.repeats));
  ROMP_CHECK(options_.warmup >= 0, "--warmup must be >= 0, got " + std::to_string(options_.warmup));
  ROMP_CHECK(options_.scale > 0.0, "--scale must be > 0");
}

std::vector<Exec> Context::execs() const {
  std::vector<Exec> execs;
  for (int threads : options_.cpu_threads) execs.push_back(Exec::cpu(threads));
  if (options_.use_cuda) execs.push_back(Exec::cuda(options_.cuda_device));
  return execs;
}

Index Context::scaled(Index nominal, Index minimum) const {
  return std::max(minimum, Index(std::llround(double(nominal) * options_.scale)));
}

const Measurement& Context::time(const std::string& suite, const std::string& name, const Exec& exec, Index items,
                                 const std::string& unit, const std::function<void()>& work, double bytes_per_item,
                                 const std::string& note) {
  for (int i = 0; i < options_.warmup; ++i) work();
  synchronize(exec);
  Measurement m{suite,          name, to_string(exec.backend), exec.is_cuda() ? 0 : exec.threads, items, unit, {},
                bytes_per_item, note};
  DeviceTimer timer(exec);
  for (int i = 0; i < options_.repeats; ++i) {
    timer.start();
    work();
    m.seconds.push_back(timer.stop());
  }
  return add(std::move(m));
}

const Measurement& Context::add(Measurement m) {
  std::string line = fmt::format("{:<8} {:<34} {:<4} {:>2}t  n={:<10} median {:.4e} s  [{:.4e}, {:.4e}]  {:.4e} {}/s",
                                 m.suite, m.name, m.backend, m.threads, m.items, m.median_seconds(), m.min_seconds(),
                                 m.max_seconds(), m.items_per_second(), m.unit);
  if (m.bytes_per_item > 0) line += fmt::format("  {:.2f} GB/s", m.gigabytes_per_second());
  fmt::print("{}\n", line);
  measurements_.push_back(std::move(m));
  return measurements_.back();
}

void Context::record(const std::string& key, double value) {
  fmt::print("{:<8} {} = {:.4g}\n", "record", key, value);
  records_.emplace_back(key, value);
}

}  // namespace romp::bench
