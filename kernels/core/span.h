// Span<T>: a non-owning view of contiguous elements in host or device memory; what kernels take.
#pragma once

#include <type_traits>

#include "kernels/core/hd.h"

namespace romp {

template <class T>
class Span {
 public:
  using element_type = T;
  using value_type = std::remove_cv_t<T>;

  Span() = default;
  ROMP_HD Span(T* data, Index size) : data_(data), size_(size) {}

  // Span<T> converts to Span<const T>, never the other way.
  template <class U, class = std::enable_if_t<std::is_convertible_v<U (*)[], T (*)[]>>>
  ROMP_HD Span(const Span<U>& other) : data_(other.data()), size_(other.size()) {}

  ROMP_HD T& operator[](Index i) const { return data_[i]; }
  ROMP_HD T* data() const { return data_; }
  ROMP_HD Index size() const { return size_; }
  ROMP_HD bool empty() const { return size_ == 0; }
  ROMP_HD T* begin() const { return data_; }
  ROMP_HD T* end() const { return data_ + size_; }
  ROMP_HD Span subspan(Index offset, Index count) const { return Span(data_ + offset, count); }

 private:
  T* data_ = nullptr;
  Index size_ = 0;
};

}  // namespace romp
