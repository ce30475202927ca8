// fill(exec, values, value): every element of `values` set to `value`, on exec's backend.
#pragma once

#include "kernels/core/exec.h"
#include "kernels/core/span.h"

namespace romp {

// Ordered on exec's stream and asynchronous on CUDA, where an upload of the same values would be a
// blocking round trip (and a CUDA graph could not hold it). Instantiated for std::int64_t (failure and search
// slots reset every substep) and float (the particle domains' stiffening).
template <class T>
void fill(const Exec& exec, Span<T> values, T value);

}  // namespace romp
