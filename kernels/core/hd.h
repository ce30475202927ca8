// Host/device annotations and the index type shared by every single-source kernel.
#pragma once

#include <cstdint>

#if defined(__CUDACC__)
#define ROMP_HD __host__ __device__
#define ROMP_HD_INLINE __host__ __device__ __forceinline__
#else
#define ROMP_HD
#define ROMP_HD_INLINE inline
#endif

// ROMP_SIMD_SUM(sum) before a loop that only adds to `sum`: the host compiler may vectorise it, summing
// in lanes (a fixed order for a given build, not the loop's). Nothing on the device, where one thread
// already works on one point.
#define ROMP_PRAGMA(text) _Pragma(#text)
#if defined(__CUDA_ARCH__) || !defined(_OPENMP)
#define ROMP_SIMD_SUM(sum)
#else
#define ROMP_SIMD_SUM(sum) ROMP_PRAGMA(omp simd reduction(+ : sum))
#endif

// ROMP_UNROLL before a loop with a compile-time trip count: fully unrolled on the device, so that arrays
// indexed by its counter stay in registers (a runtime index puts them in local memory). Nothing on the
// host, whose compiler unrolls by its own measure.
#if defined(__CUDA_ARCH__)
#define ROMP_UNROLL ROMP_PRAGMA(unroll)
#define ROMP_NO_UNROLL ROMP_PRAGMA(unroll 1)
#else
#define ROMP_UNROLL
#define ROMP_NO_UNROLL
#endif

namespace romp {

// Element counts and indices. 64-bit so particle and node counts never overflow.
using Index = std::int64_t;

}  // namespace romp
