// dense_forward and dense_backward: one functor per output row, each an axpy loop over a contiguous row.
#include "kernels/mlp/dense_layer.h"

#include "kernels/core/for_each.h"

namespace romp::mlp {
namespace {

// out[0, count) = Σ_k a[k] b[k · count + j] for j < count: a row times a row-major matrix.
template <class T>
ROMP_HD_INLINE void row_times_matrix(const T* a, int terms, const T* b, int count, T* out) {
  for (int j = 0; j < count; ++j) out[j] = T(0);
  for (int k = 0; k < terms; ++k) {
    const T factor = a[k];
    const T* row = b + Index(k) * count;
    for (int j = 0; j < count; ++j) out[j] += factor * row[j];
  }
}

// Row r of out = A B for row-major A [rows, terms] and B [terms, count]: Y = X Wᵀ (A = X, B = Wᵀ)
// and dX = dY W (A = dY, B = W).
template <class T>
struct RowsTimesMatrix {
  Span<const T> A;
  int terms;
  Span<const T> B;
  int count;
  Span<T> out;
  ROMP_HD void operator()(Index r) const {
    row_times_matrix(A.data() + r * terms, terms, B.data(), count, out.data() + r * count);
  }
};

// Row o of dW = dYᵀ X: Σ_r dY[r][o] X[r], summed over rows in order.
template <class T>
struct WeightGradientRow {
  DenseShape shape;
  Span<const T> X, dY;
  Span<T> dW;
  ROMP_HD void operator()(Index o) const {
    T* out = dW.data() + o * shape.inputs;
    for (int i = 0; i < shape.inputs; ++i) out[i] = T(0);
    for (Index r = 0; r < shape.rows; ++r) {
      const T factor = dY[r * shape.outputs + o];
      const T* row = X.data() + r * shape.inputs;
      for (int i = 0; i < shape.inputs; ++i) out[i] += factor * row[i];
    }
  }
};

}  // namespace

template <class T>
void dense_forward(const Exec& exec, const DenseShape& shape, Span<const T> X, Span<const T> W_t, Span<T> Y) {
  for_each(exec, shape.rows, RowsTimesMatrix<T>{X, shape.inputs, W_t, shape.outputs, Y});
}

template <class T>
void dense_backward(const Exec& exec, const DenseShape& shape, Span<const T> X, Span<const T> W, Span<const T> dY,
                    Span<T> dX, Span<T> dW) {
  for_each(exec, shape.rows, RowsTimesMatrix<T>{dY, shape.outputs, W, shape.inputs, dX});
  for_each(exec, shape.outputs, WeightGradientRow<T>{shape, X, dY, dW});
}

#define ROMP_DENSE_LAYER(T)                                                                                    \
  template void dense_forward<T>(const Exec&, const DenseShape&, Span<const T>, Span<const T>, Span<T>);       \
  template void dense_backward<T>(const Exec&, const DenseShape&, Span<const T>, Span<const T>, Span<const T>, \
                                  Span<T>, Span<T>);
ROMP_DENSE_LAYER(float)
ROMP_DENSE_LAYER(double)
#undef ROMP_DENSE_LAYER

}  // namespace romp::mlp
