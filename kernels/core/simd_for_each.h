// romp::simd_for_each(exec, n, functor): for_each whose CPU loop runs one element per SIMD lane.
//
// romp::for_each's OpenMP loop runs one element per iteration; here each thread takes chunks of elements
// and one SIMD lane computes one element. It pays for functors that are branch-free (or whose branches
// the compiler can turn into masks) and fully inlined, and whose math functions vectorise (kernels/math:
// select, rsqrt, exp, erf; a libm call keeps the loop scalar). On x86-64 with GCC the SIMD loop is also
// compiled for AVX2 (x86-64-v3) and AVX-512 (x86-64-v4), and the loader picks the widest the CPU supports:
// the project's baseline flags target SSE2, four floats per vector. The wider clones may also contract
// a b + c into FMA instructions, so CPUs of different ISA levels can differ in the last bits; on one
// machine, results do not depend on the thread count. On CUDA it is for_each.
#pragma once

#include <omp.h>

#include "kernels/core/for_each.h"
#include "kernels/core/memory.h"

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__CUDA_ARCH__)
#define ROMP_SIMD_CLONES __attribute__((target_clones("default", "arch=x86-64-v3", "arch=x86-64-v4")))
#else
#define ROMP_SIMD_CLONES
#endif

namespace romp {
namespace detail {

// Elements per chunk: a few AVX-512 vectors, small enough to balance the threads' work and keep a
// chunk's planes in L1; larger chunks measured no faster (the batched SVD).
inline constexpr Index kSimdChunk = 64;

template <class Element>
ROMP_SIMD_CLONES void run_simd(const Element& element, Index begin, Index end) {
#pragma omp simd
  for (Index i = begin; i < end; ++i) element(i);
}

// block(begin, size) for consecutive chunks of `chunk` elements (the last one shorter), spread over exec's
// threads: the host loop of kernels that work on several elements at once.
template <class Block>
void for_each_chunk_cpu(const Exec& exec, Index count, Index chunk, const Block& block) {
  const Index chunks = (count + chunk - 1) / chunk;
  const memory::DeviceAccess launch;
#pragma omp parallel for schedule(static) num_threads(cpu_threads(exec))
  for (Index c = 0; c < chunks; ++c) {
    const Index begin = c * chunk;
    block(begin, begin + chunk < count ? chunk : count - begin);
  }
}

template <class Element>
void simd_for_each_cpu(const Exec& exec, Index count, const Element& element) {
  for_each_chunk_cpu(exec, count, kSimdChunk, [&](Index begin, Index size) { run_simd(element, begin, begin + size); });
}

}  // namespace detail

template <class Element>
void simd_for_each(const Exec& exec, Index count, const Element& element) {
  if (exec.is_cuda()) {
    for_each(exec, count, element);
  } else if (count > 0) {
    memory::launch_on_cpu(exec.stream, 1, [exec, count, element] { detail::simd_for_each_cpu(exec, count, element); });
  }
}

}  // namespace romp
