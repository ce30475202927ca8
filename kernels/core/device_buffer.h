// DeviceBuffer<T>: move-only owner of n elements in host or CUDA memory, with explicit transfers.
#pragma once

#include <type_traits>
#include <utility>
#include <vector>

#include "kernels/core/error.h"
#include "kernels/core/exec.h"
#include "kernels/core/memory.h"
#include "kernels/core/span.h"

namespace romp {

// Host ↔ backend copies of a view of backend memory (a buffer, its prefix, one element), counted in
// memory::traffic().
template <class T>
void upload(Backend backend, Span<T> device, Span<const T> host, Stream stream = nullptr) {
  ROMP_CHECK(host.size() == device.size(),
             "upload: " + std::to_string(host.size()) + " host elements into " + std::to_string(device.size()));
  memory::upload(device.data(), backend, host.data(), std::size_t(host.size()) * sizeof(T), stream);
}
template <class T>
std::vector<std::remove_const_t<T>> download(Backend backend, Span<T> device, Stream stream = nullptr) {
  std::vector<std::remove_const_t<T>> host(static_cast<std::size_t>(device.size()));
  memory::download(host.data(), device.data(), backend, host.size() * sizeof(T), stream);
  return host;
}

template <class T>
class DeviceBuffer {
  static_assert(std::is_trivially_copyable_v<T>, "DeviceBuffer holds trivially copyable elements");

 public:
  DeviceBuffer() = default;
  // Uninitialised storage for `size` elements; call fill_zero() or copy_from_host() before reading.
  DeviceBuffer(Backend backend, Index size)
      : backend_(backend), size_(checked_size(size)), data_(static_cast<T*>(memory::allocate(backend, bytes()))) {}

  static DeviceBuffer from_host(Backend backend, Span<const T> host, Stream stream = nullptr) {
    DeviceBuffer buffer(backend, host.size());
    buffer.copy_from_host(host, stream);
    return buffer;
  }
  static DeviceBuffer from_host(Backend backend, const std::vector<T>& host, Stream stream = nullptr) {
    return from_host(backend, Span<const T>(host.data(), Index(host.size())), stream);
  }

  ~DeviceBuffer() { memory::release(backend_, data_); }

  // Copying device memory is a deliberate act (clone()), never an accident of passing by value.
  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;

  DeviceBuffer(DeviceBuffer&& other) noexcept
      : backend_(other.backend_), size_(std::exchange(other.size_, 0)), data_(std::exchange(other.data_, nullptr)) {}
  DeviceBuffer& operator=(DeviceBuffer&& other) noexcept {
    if (this != &other) {
      memory::release(backend_, data_);
      backend_ = other.backend_;
      size_ = std::exchange(other.size_, 0);
      data_ = std::exchange(other.data_, nullptr);
    }
    return *this;
  }

  Backend backend() const { return backend_; }
  Index size() const { return size_; }
  bool empty() const { return size_ == 0; }
  std::size_t bytes() const { return std::size_t(size_) * sizeof(T); }
  T* data() { return data_; }
  const T* data() const { return data_; }
  Span<T> span() { return Span<T>(data_, size_); }
  Span<const T> span() const { return Span<const T>(data_, size_); }

  void copy_from_host(Span<const T> host, Stream stream = nullptr) {
    ROMP_CHECK(host.size() == size_, "copy_from_host: " + std::to_string(host.size()) +
                                         " host elements into a buffer of " + std::to_string(size_));
    upload(backend_, span(), host, stream);
  }
  void copy_to_host(Span<T> host, Stream stream = nullptr) const {
    ROMP_CHECK(host.size() == size_, "copy_to_host: buffer of " + std::to_string(size_) + " into " +
                                         std::to_string(host.size()) + " host elements");
    memory::download(host.data(), data_, backend_, bytes(), stream);
  }
  std::vector<T> to_host(Stream stream = nullptr) const { return download(backend_, span(), stream); }

  // For buffers refilled every step with a count that varies: at least n elements, grown to n and a
  // quarter when short, so the allocation happens only when the count outgrows every earlier one. The
  // contents are not kept. Use prefix(count) for this step's elements.
  void ensure_size(Backend backend, Index n) {
    if (size_ < n || (backend != backend_ && n > 0)) *this = DeviceBuffer(backend, n + n / 4);
  }
  // Uploads `host` into the first host.size() elements, growing the buffer as ensure_size does, and
  // returns them: a buffer refilled from the host every step without allocating each time.
  Span<T> upload_front(Backend backend, const std::vector<T>& host, Stream stream = nullptr) {
    const Index n = Index(host.size());
    ensure_size(backend, n);
    upload(backend, prefix(n), Span<const T>(host.data(), n), stream);
    return prefix(n);
  }
  Span<T> prefix(Index count) { return span().subspan(0, checked_prefix(count)); }
  Span<const T> prefix(Index count) const { return span().subspan(0, checked_prefix(count)); }

  DeviceBuffer clone(Stream stream = nullptr) const { return clone_to(backend_, stream); }
  DeviceBuffer clone_to(Backend backend, Stream stream = nullptr) const {
    DeviceBuffer copy(backend, size_);
    memory::copy(copy.data_, backend, data_, backend_, bytes(), stream);
    return copy;
  }

  void fill_zero(Stream stream = nullptr) { memory::fill_zero(data_, backend_, bytes(), stream); }

 private:
  Index checked_prefix(Index count) const {
    ROMP_CHECK(count >= 0 && count <= size_,
               "prefix of " + std::to_string(count) + " elements in a buffer of " + std::to_string(size_));
    return count;
  }
  static Index checked_size(Index size) {
    ROMP_CHECK(size >= 0, "DeviceBuffer size must be non-negative, got " + std::to_string(size));
    return size;
  }

  Backend backend_ = Backend::Cpu;
  Index size_ = 0;
  T* data_ = nullptr;
};

}  // namespace romp
