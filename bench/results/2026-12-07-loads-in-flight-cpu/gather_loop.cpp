// The particles' permutation loop on the CPU, before (plane by plane) and after (romp::copy_row), on 26 float planes
// of 1,290,555 rows through the identity order (the memory suite's gather_rows size). Medians of 12.
//   g++ -O3 -fopenmp -I../../.. gather_loop.cpp -o gather_loop && OMP_NUM_THREADS=1 ./gather_loop
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "kernels/core/gather_planes.h"

int main() {
  using romp::Index;
  const Index rows = 1290555;
  const int planes = 26;
  std::vector<float> source(std::size_t(rows * planes), 1.0f), destination(source.size());
  std::vector<std::int32_t> order(static_cast<std::size_t>(rows));
  for (Index i = 0; i < rows; ++i) order[std::size_t(i)] = std::int32_t(i);
  for (const bool batched : {false, true}) {
    std::vector<double> seconds;
    for (int repeat = 0; repeat < 12; ++repeat) {
      const auto start = std::chrono::steady_clock::now();
      if (batched) {
#pragma omp parallel for schedule(static)
        for (Index i = 0; i < rows; ++i)
          romp::copy_row(source.data(), rows, Index(order[std::size_t(i)]), destination.data(), rows, i, planes);
      } else {
#pragma omp parallel for schedule(static)
        for (Index i = 0; i < rows; ++i)
          for (int c = 0; c < planes; ++c)
            destination[std::size_t(c * rows + i)] = source[std::size_t(c * rows + order[std::size_t(i)])];
      }
      seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    std::sort(seconds.begin(), seconds.end());
    std::printf("%s: median %.4f s\n", batched ? "copy_row" : "plane by plane", seconds[6]);
  }
}
