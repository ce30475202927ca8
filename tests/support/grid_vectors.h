// Test helpers for the implicit step's flat vectors (3 planes over grid nodes and domain corners)
// and for reading the sparse grid's node coordinates on the host.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "kernels/core/exec.h"
#include "kernels/core/memory.h"
#include "kernels/mpm/sparse_grid.h"

namespace romp::test {

// `grid` with its block keys copied to `keys` on the host, so that GridNode works there on any backend.
inline mpm::GridView with_host_block_keys(const Exec& exec, const mpm::GridView& grid,
                                          std::vector<std::uint64_t>& keys) {
  keys.resize(grid.blocks);
  memory::copy(keys.data(), Backend::Cpu, grid.table.block_keys.data(), exec.backend,
               keys.size() * sizeof(std::uint64_t), exec.stream);
  mpm::GridView host_grid = grid;
  host_grid.table.block_keys = Span<std::uint64_t>(keys.data(), grid.blocks);
  return host_grid;
}

// The dot product in double.
inline double dot(const std::vector<float>& a, const std::vector<float>& b) {
  double sum = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) sum += double(a[k]) * double(b[k]);
  return sum;
}

// Standard normal entries where `free` is 1, zero where it is 0.
inline std::vector<float> random_free_vector(const std::vector<float>& free, std::mt19937_64& rng) {
  std::normal_distribution<float> normal;
  std::vector<float> x(free.size());
  for (std::size_t k = 0; k < x.size(); ++k) x[k] = free[k] * normal(rng);
  return x;
}

}  // namespace romp::test
