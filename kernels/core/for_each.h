// romp::for_each(exec, n, functor): runs functor(i) for i in [0, n) as a CUDA kernel or an OpenMP loop.
//
// The functor's operator()(Index) is ROMP_HD, so one definition serves both backends. A translation
// unit that launches on CUDA must be compiled by nvcc (a .cu file; see romp_single_source in
// cmake/RompCuda.cmake); the same file compiled as C++ keeps only the CPU path.
#pragma once

#include <omp.h>

#include <algorithm>
#include <climits>
#include <cstdint>
#include <string>
#include <type_traits>

#include "kernels/core/error.h"
#include "kernels/core/exec.h"
#include "kernels/core/guarded_memory.h"
#include "kernels/core/hd.h"
#include "kernels/core/memory.h"
#include "kernels/core/span.h"

#if defined(__CUDACC__)
#include "kernels/core/cuda_check.h"
#endif

namespace romp {
namespace detail {

// The OpenMP threads a CPU loop on `exec` runs on.
inline int cpu_threads(const Exec& exec) { return exec.threads > 0 ? exec.threads : omp_get_max_threads(); }

template <class F>
void for_each_cpu(const Exec& exec, Index n, const F& functor) {
  const int threads = cpu_threads(exec);
  const memory::DeviceAccess launch;
#pragma omp parallel for schedule(static) num_threads(threads)
  for (Index i = 0; i < n; ++i) functor(i);
}

// Threads per block for element-wise launches that take several elements a thread or loop over a bound: a
// multiple of the warp size that keeps occupancy high on sm_80/sm_90 for register-light functors.
inline constexpr int kForEachBlockSize = 256;
// for_each's default block size: the occupancy calculator's for the functor's kernel (block_size_for).
inline constexpr int kOccupancyBlockSize = 0;

// ROMP_FOR_EACH_BLOCK_SIZE, read once: 0 (unset) lets block_size_for choose; a multiple of 32 in [32, 1024] fixes the
// block size of every one-element launch that names none, or the largest a kernel's registers allow where that is
// less (an A/B against the calculator's, tools/device_run.sh).
// parse_block_size throws romp::Error on any other value, naming the variable and the allowed range.
int parse_block_size(const char* value);
int forced_block_size();

// Threads per block for n elements of one element a thread: the block size at which the kernel reaches its highest
// occupancy (`occupancy_best`, from its registers), made smaller when n is too few to give each of the device's
// `multiprocessors` a block (a thousand particles in blocks of 256 would run on 4 SMs of 132), never below a warp.
// Why not 256 for all: at 96 registers a thread, blocks of 256 leave an SM 16 warps, blocks of 224 or 672 leave
// it 21 (bench/results/gpu-notes.md).
inline int block_size_for(Index n, int occupancy_best, int multiprocessors) {
  constexpr int kWarp = 32;
  const Index per_multiprocessor = (n + multiprocessors - 1) / std::max(multiprocessors, 1);
  const Index spread = per_multiprocessor / kWarp * kWarp;  // whole warps, rounded down: no SM left without a block
  return int(std::max<Index>(kWarp, std::min<Index>(occupancy_best, spread)));
}

// The elements one CUDA thread of a for_each launch takes: F::kItemsPerThread where the functor declares it, else 1.
// A light, memory-bound functor (a copy) loads one value and waits for it before its store: with one load in
// flight per thread the H200 copies at 71 % of cudaMemcpy's rate. A functor that reads through read_only
// (read_only.h) and declares K elements a thread keeps K loads in flight (bench/results/gpu-notes.md).
template <class F, class = void>
inline constexpr int kItemsPerThread = 1;
template <class F>
inline constexpr int kItemsPerThread<F, std::void_t<decltype(F::kItemsPerThread)>> = F::kItemsPerThread;

// A launch's tiles: block b, thread t covers elements tile_element(b, t, k) for k < items, `block_size` apart so
// that each of a warp's loads stays coalesced; tile_count tiles cover n elements.
ROMP_HD inline Index tile_element(Index block, int thread, int k, int block_size, int items) {
  return (block * items + k) * block_size + thread;
}
inline Index tile_count(Index n, int block_size, int items) {
  const Index tile = Index(block_size) * items;
  return (n + tile - 1) / tile;
}

#if defined(__CUDACC__)
// After a launch on exec's stream, from for_each and from the custom kernels alike: the launch's own
// error, and in debug builds (or with ROMP_SYNC_LAUNCHES) any fault of the kernel, surfaced at the launch
// that caused it.
inline void check_launch(const Exec& exec) {
  ROMP_CUDA_CHECK(cudaGetLastError());
#if !defined(NDEBUG) || defined(ROMP_SYNC_LAUNCHES)
  // Not while a graph is captured: the launch is recorded, not run, and a wait would end the capture.
  if (memory::open_capture() == nullptr) ROMP_CUDA_CHECK(cudaStreamSynchronize(exec.stream));
#endif
}

template <int kBlockSize, int kItems, class F>
__global__ void for_each_kernel(Index n, F functor) {
  if constexpr (kItems == 1) {
    // What a functor that declares nothing gets: the one-element kernel as it was before tiles.
    const Index i = Index(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i < n) functor(i);
  } else {
    const auto element = [](int k) { return tile_element(blockIdx.x, threadIdx.x, k, kBlockSize, kItems); };
    if (element(kItems - 1) < n) {
      // A whole tile: no bound check between the calls, so their read-only loads can be issued together.
      ROMP_UNROLL
      for (int k = 0; k < kItems; ++k) functor(element(k));
    } else {
      ROMP_UNROLL
      for (int k = 0; k < kItems - 1; ++k) {
        if (element(k) < n) functor(element(k));
      }
    }
  }
}

// While it lives, this thread may make calls a stream capture would otherwise refuse (the launch shape's device
// queries below run at a kernel's first launch, which may fall inside a capture of a frame's substeps).
class RelaxedCapture {
 public:
  RelaxedCapture() { ROMP_CUDA_CHECK(cudaThreadExchangeStreamCaptureMode(&mode_)); }
  ~RelaxedCapture() { cudaThreadExchangeStreamCaptureMode(&mode_); }
  RelaxedCapture(const RelaxedCapture&) = delete;
  RelaxedCapture& operator=(const RelaxedCapture&) = delete;

 private:
  cudaStreamCaptureMode mode_ = cudaStreamCaptureModeRelaxed;
};

// The current device's multiprocessors (asked once).
inline int multiprocessor_count() {
  static const int count = [] {
    const RelaxedCapture relaxed;
    int device = 0, multiprocessors = 0;
    ROMP_CUDA_CHECK(cudaGetDevice(&device));
    ROMP_CUDA_CHECK(cudaDeviceGetAttribute(&multiprocessors, cudaDevAttrMultiProcessorCount, device));
    return std::max(multiprocessors, 1);
  }();
  return count;
}

// F's one-element kernel: the block size at which it reaches its highest occupancy, and the largest it can launch
// (its registers allow), asked of the occupancy calculator once per functor type.
struct BlockSizes {
  int best = 32;
  int most = 32;
};
template <class F>
BlockSizes block_sizes() {
  static const BlockSizes sizes = [] {
    const RelaxedCapture relaxed;
    const auto kernel = for_each_kernel<kForEachBlockSize, 1, F>;
    int min_grid = 0, best = 0;
    ROMP_CUDA_CHECK(cudaOccupancyMaxPotentialBlockSize(&min_grid, &best, kernel, 0, 0));
    cudaFuncAttributes attributes{};
    ROMP_CUDA_CHECK(cudaFuncGetAttributes(&attributes, kernel));
    return BlockSizes{std::max(best, 32), std::max(attributes.maxThreadsPerBlock / 32 * 32, 32)};
  }();
  return sizes;
}

template <int kBlockSize, class F>
void for_each_cuda(const Exec& exec, Index n, const F& functor) {
  constexpr int kItems = kItemsPerThread<F>;
  static_assert(kItems >= 1, "a functor's kItemsPerThread is at least 1");
  // Tiles of several elements a thread index by a block size fixed at compile time.
  constexpr int kFixedBlock = kBlockSize == kOccupancyBlockSize ? kForEachBlockSize : kBlockSize;
  constexpr bool kOccupancy = kBlockSize == kOccupancyBlockSize && kItems == 1;
  int block = kFixedBlock;
  if constexpr (kOccupancy) {
    const BlockSizes sizes = block_sizes<F>();
    const int forced = forced_block_size();  // at most what the kernel's registers allow
    block = forced > 0 ? std::min(forced, sizes.most) : block_size_for(n, sizes.best, multiprocessor_count());
  }
  const Index blocks = tile_count(n, block, kItems);
  ROMP_CHECK(blocks <= INT_MAX, "for_each: " + std::to_string(n) + " elements exceed one CUDA launch");
  for_each_kernel<kFixedBlock, kItems><<<unsigned(blocks), unsigned(block), 0, exec.stream>>>(n, functor);
  check_launch(exec);
}

// functor(i) for i < min(bound, count[0]) (count null: bound) in a grid-stride loop: the grid is sized for the
// bound, which the host knows, and each thread reads the count, which stays on the device.
template <class F>
__global__ void for_each_bounded_kernel(Index bound, const std::int64_t* count, F functor) {
  const Index n = count && *count < bound ? Index(*count) : bound;
  const Index stride = Index(gridDim.x) * blockDim.x;
  for (Index i = Index(blockIdx.x) * blockDim.x + threadIdx.x; i < n; i += stride) functor(i);
}

// The blocks of kBlockSize threads of `kernel` the device holds at once (every SM at the kernel's occupancy, from
// its registers and shared memory): what a grid-stride launch needs to keep the device busy. Asked of the
// occupancy calculator once per kernel (the current device's, at the first call).
template <int kBlockSize, class Kernel>
int resident_blocks(Kernel kernel) {
  static const int blocks = [kernel] {
    const RelaxedCapture relaxed;
    int per_multiprocessor = 0;
    ROMP_CUDA_CHECK(cudaOccupancyMaxActiveBlocksPerMultiprocessor(&per_multiprocessor, kernel, kBlockSize, 0));
    return std::max(per_multiprocessor, 1) * multiprocessor_count();
  }();
  return blocks;
}

// A bounded launch whose elements past the count cost nothing: at most one resident wave of blocks, however large
// the bound (a launch of the bound's threads, most of them reading the count and leaving, would take a wave of the
// device per few hundred thousand of them: at millions of points that is longer than the live elements' work).
template <int kBlockSize, class F>
void for_each_bounded_cuda(const Exec& exec, Index bound, const std::int64_t* count, const F& functor) {
  const Index needed = (bound + kBlockSize - 1) / kBlockSize;
  const Index blocks = std::min<Index>(needed, resident_blocks<kBlockSize>(for_each_bounded_kernel<F>));
  for_each_bounded_kernel<<<unsigned(blocks), kBlockSize, 0, exec.stream>>>(bound, count, functor);
  check_launch(exec);
}
#endif

// How a launch covers its elements: every one of them, or those below a count on the device (a bound).
enum class Cover { Each, UpToCount };

// One launch of functor(i) for i in [0, n) (UpToCount: i < min(n, count[0]), count empty: n), counted (or
// recorded into an open capture on the CPU).
template <Cover kCover, int kBlockSize, class F>
void launch(const Exec& exec, Index n, Span<const std::int64_t> count, const F& functor) {
#if defined(ROMP_WITH_CUDA) && !defined(__CUDACC__)
  // In a build with the CUDA backend, a launch from a file nvcc does not compile would throw at run
  // time on a GPU only: refuse it at compile time, where CI (nvcc, no GPU) sees it.
  static_assert(sizeof(F) == 0,
                "romp::for_each in a translation unit nvcc does not compile: move the launch to a .cu file "
                "listed with romp_single_source()");
#endif
  if (n <= 0) return;
  if (exec.is_cuda()) {
#if defined(__CUDACC__)
    memory::note_launch();
    if constexpr (kCover == Cover::UpToCount)
      for_each_bounded_cuda<kBlockSize>(exec, n, count.empty() ? nullptr : count.data(), functor);
    else
      for_each_cuda<kBlockSize>(exec, n, functor);
    return;
#else
    throw Error(
        "for_each on the CUDA backend from a translation unit not compiled by nvcc; "
        "launch it from a .cu file listed with romp_single_source()");
#endif
  }
  // The CPU reads the count when the launch runs (in a replayed graph too) and loops over the live prefix alone,
  // which a loop over the bound would hand to the first of its threads.
  memory::launch_on_cpu(exec.stream, 1, [exec, n, count, functor] {
    Index live = n;
    if (!count.empty()) {
      const memory::DeviceAccess read;
      live = count[0] < n ? Index(count[0]) : n;
    }
    if (live > 0) for_each_cpu(exec, live, functor);
  });
}

}  // namespace detail

// One launch (memory::traffic().launches counts it) of functor(i) for i in [0, n). kBlockSize: threads per
// CUDA block; by default the occupancy calculator's for the functor, smaller where n is too few to reach every SM
// (detail::block_size_for). Light streaming functors declare kItemsPerThread (blocks of 256 then).
template <int kBlockSize = detail::kOccupancyBlockSize, class F>
void for_each(const Exec& exec, Index n, const F& functor) {
  detail::launch<detail::Cover::Each, kBlockSize>(exec, n, {}, functor);
}

// functor(i) for i < min(bound, count[0]) (count a value on exec's backend; empty: every i < bound): one launch
// whenever bound > 0, sized on the host by the bound while the count stays where a device computed it (no round
// trip to learn it). CUDA launches at most one resident wave of blocks, each thread looping over the live
// elements in strides of the grid; the CPU loops over the live elements alone.
template <int kBlockSize = detail::kForEachBlockSize, class F>
void for_each_bounded(const Exec& exec, Index bound, Span<const std::int64_t> count, const F& functor) {
  detail::launch<detail::Cover::UpToCount, kBlockSize>(exec, bound, count, functor);
}

}  // namespace romp
