// Shared by the I/O tests: a fresh folder per test, random snapshot contents and file helpers.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "kernels/core/error.h"
#include "nn/io/snapshot_layout.h"
#include "tests/support/scratch_folder.h"

namespace romp::io::testing {

// A folder of its own for each test, removed afterwards.
class IoTest : public ::testing::Test {
 protected:
  std::string file(const std::string& name) const { return folder_.file(name); }
  std::vector<std::string> folder_contents() const { return folder_.contents(); }

  romp::test::ScratchFolder folder_;
};

using romp::test::error_message;

inline std::vector<float> random_floats(std::size_t count, std::mt19937& random) {
  std::normal_distribution<float> normal(0.0f, 10.0f);
  std::vector<float> values(count);
  for (float& value : values) value = normal(random);
  return values;
}

// A header for n particles with random arrays and a two-parameter μ.
inline SnapshotHeader random_header(std::int64_t n, std::mt19937& random) {
  SnapshotHeader header;
  header.X = random_floats(std::size_t(3 * n), random);
  header.mass = random_floats(std::size_t(n), random);
  header.volume0 = random_floats(std::size_t(n), random);
  std::uniform_int_distribution<std::int32_t> material(0, 4);
  header.material.resize(std::size_t(n));
  for (std::int32_t& id : header.material) id = material(random);
  header.scene = "[scene]\nname = \"test\"\n# résolu\n";
  header.parameter_names = {"E", "nu"};
  header.parameter_values = {1e5, 0.3};
  header.romp_version = "0.1.0";
  header.commit = "abc1234-dirty";
  return header;
}

// A frame with random values in every field (also the ones a writer may not select).
inline FrameData random_frame(std::int64_t n, double time, std::int64_t step, std::mt19937& random) {
  FrameData frame;
  frame.time = time;
  frame.step = step;
  frame.x = random_floats(std::size_t(3 * n), random);
  frame.v = random_floats(std::size_t(3 * n), random);
  frame.F = random_floats(std::size_t(9 * n), random);
  frame.C = random_floats(std::size_t(9 * n), random);
  return frame;
}

inline bool bitwise_equal(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

inline std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace romp::io::testing
