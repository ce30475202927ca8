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

namespace romp {

// Element counts and indices. 64-bit so particle and node counts never overflow.
using Index = std::int64_t;

}  // namespace romp
