// Level-1 vector operations as single-source element-wise functors.
#include "kernels/core/vector_ops.h"

#include <string>

#include "kernels/core/error.h"
#include "kernels/core/for_each.h"
#include "kernels/core/read_only.h"

namespace romp {
namespace {

// Streaming functors (for_each.h): four elements a CUDA thread, x read through the read-only path, so that a
// thread's loads go out together (y's are a block apart, which ptxas can tell from its stores).
struct Axpy {
  static constexpr int kItemsPerThread = 4;
  float alpha;
  Span<const float> x;
  Span<float> y;
  ROMP_HD void operator()(Index k) const { y[k] += alpha * read_only(x, k); }
};

struct Xpby {
  static constexpr int kItemsPerThread = 4;
  Span<const float> x;
  float beta;
  Span<float> y;
  ROMP_HD void operator()(Index k) const { y[k] = read_only(x, k) + beta * y[k]; }
};

struct DotLanes {
  Span<const float> a, b;
  Span<double> lanes;
  ROMP_HD void operator()(Index lane) const {
    double sum = 0.0;
    for (Index k = lane; k < a.size(); k += lanes.size()) sum += double(a[k]) * double(b[k]);
    lanes[lane] = sum;
  }
};

void check_sizes(Index a, Index b, const char* operation) {
  ROMP_CHECK(a == b,
             std::string(operation) + ": spans of " + std::to_string(a) + " and " + std::to_string(b) + " elements");
}

}  // namespace

void axpy(const Exec& exec, float alpha, Span<const float> x, Span<float> y) {
  check_sizes(x.size(), y.size(), "axpy");
  for_each(exec, y.size(), Axpy{alpha, x, y});
}

void xpby(const Exec& exec, Span<const float> x, float beta, Span<float> y) {
  check_sizes(x.size(), y.size(), "xpby");
  for_each(exec, y.size(), Xpby{x, beta, y});
}

double DotProduct::operator()(const Exec& exec, Span<const float> a, Span<const float> b) {
  check_sizes(a.size(), b.size(), "dot");
  for_each(exec, kLanes, DotLanes{a, b, lanes_.span()});
  lanes_.copy_to_host(Span<double>(host_.data(), kLanes), exec.stream);
  double sum = 0.0;
  for (double lane : host_) sum += lane;
  return sum;
}

}  // namespace romp
