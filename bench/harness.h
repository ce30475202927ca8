// romp-bench's measuring harness: warm-up, repeats, medians, and the record of where it ran.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "kernels/core/exec.h"
#include "kernels/core/hd.h"

namespace romp::bench {

struct Options {
  int warmup = 2;      // untimed runs before the timed ones
  int repeats = 10;    // timed runs; the median is reported
  double scale = 1.0;  // multiplies each suite's problem sizes (smaller for smoke runs)
  std::vector<int> cpu_threads{1, 2};
  bool use_cuda = false;  // measure on the CUDA device as well as the CPU
  int cuda_device = 0;
  // The rom suite's case: a scene, its parameter overrides, and a model trained on the scene's sweep.
  std::string scene;
  std::map<std::string, double> parameters;
  std::string rom_model;
  std::vector<int> rom_samples{10, 50, 0};  // sample counts of the reduced cases (0: every point)
};

// One timed case: `items` units of work per repeat (SVDs, particle-substeps, bytes, ...).
struct Measurement {
  std::string suite;    // "svd", "memory", ...
  std::string name;     // what was run, e.g. "romp_svd3<float>", "eigen_jacobi_svd<float>"
  std::string backend;  // "cpu" or "cuda"
  int threads = 0;      // CPU threads; 0 on CUDA
  Index items = 0;
  std::string unit;             // what one item is, e.g. "svd"
  std::vector<double> seconds;  // one entry per timed repeat
  double bytes_per_item = 0.0;  // when > 0, the report adds effective GB/s
  std::string note;             // free text: reference bound, baseline it compares against, ...

  double median_seconds() const;
  double min_seconds() const;
  double max_seconds() const;
  double items_per_second() const { return double(items) / median_seconds(); }
  double gigabytes_per_second() const { return bytes_per_item * double(items) / median_seconds() * 1e-9; }
};

class Context {
 public:
  Context(Options options, std::string command_line);

  const Options& options() const { return options_; }
  // The places to measure: the CPU at each requested thread count, then the CUDA device if asked.
  std::vector<Exec> execs() const;
  // Scales a suite's nominal size by --scale, never below `minimum`.
  Index scaled(Index nominal, Index minimum = 1) const;

  // Runs `work` options().warmup times untimed, then options().repeats times, each timed with a
  // DeviceTimer on `exec` (CUDA events on a GPU, steady clock on the CPU). The result is printed
  // as one line, kept for the report, and returned.
  const Measurement& time(const std::string& suite, const std::string& name, const Exec& exec, Index items,
                          const std::string& unit, const std::function<void()>& work, double bytes_per_item = 0.0,
                          const std::string& note = "");
  // Adds a measurement taken some other way (for instance by a library's own timer).
  const Measurement& add(Measurement measurement);
  // Key facts of the run printed and stored beside the measurements (e.g. a ratio between two cases).
  void record(const std::string& key, double value);

  const std::vector<Measurement>& measurements() const { return measurements_; }
  const std::vector<std::pair<std::string, double>>& records() const { return records_; }
  const std::string& command_line() const { return command_line_; }

 private:
  Options options_;
  std::string command_line_;
  std::vector<Measurement> measurements_;
  std::vector<std::pair<std::string, double>> records_;
};

// A suite is a function that measures into the context.
struct Suite {
  const char* name;
  const char* summary;
  void (*run)(Context& context);
};

}  // namespace romp::bench
