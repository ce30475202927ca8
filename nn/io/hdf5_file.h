// HDF5 files through the C API: owning handles, typed datasets and attributes, and failures as
// romp::Error messages that name the file and the object ("snapshot out.h5: dataset /frames/000003/x: missing").
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "kernels/core/error.h"
#include "nn/io/unusable_file_error.h"

namespace romp::io::hdf5 {

// Dataset dimensions, slowest-varying first (row-major, as HDF5, h5py and ParaView read them).
using Shape = std::vector<std::uint64_t>;

// The element types datasets hold: each maps to one little-endian HDF5 file type.
template <class T>
inline constexpr bool kIsElement = std::is_same_v<T, float> || std::is_same_v<T, double> ||
                                   std::is_same_v<T, std::int32_t> || std::is_same_v<T, std::int64_t>;

// Owns one HDF5 identifier and closes it with the matching H5?close. Move-only.
class Handle {
 public:
  using Closer = int (*)(std::int64_t);

  Handle() = default;
  Handle(std::int64_t id, Closer closer) : id_(id), closer_(closer) {}
  Handle(Handle&& other) noexcept;
  Handle& operator=(Handle&& other) noexcept;
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle();

  std::int64_t id() const { return id_; }
  bool valid() const { return id_ >= 0; }
  // Closes now and reports whether HDF5 succeeded (a file close also writes what is cached).
  bool close();

 private:
  std::int64_t id_ = -1;
  Closer closer_ = nullptr;
};

// A group of an open file (the root group for a File). Paths are relative to this group ("x",
// "frames/000003/x") or absolute ("/particles/X"); writes create missing intermediate groups.
class Group {
 public:
  // "/" for the root group.
  const std::string& path() const { return path_; }
  // "<role> <file name>", the prefix of every message about this file.
  const std::string& label() const { return *label_; }

  // Whether every link on the way to `path` exists.
  bool exists(const std::string& path) const;
  bool is_group(const std::string& path) const;
  bool is_dataset(const std::string& path) const;
  Group open_group(const std::string& path) const;
  Group create_group(const std::string& path);
  // Names of the links in this group, in increasing name order.
  std::vector<std::string> list() const;
  // Unlinks the object at `path`; the space it used is not reclaimed in the file.
  void remove(const std::string& path);

  template <class T>
  void write_dataset(const std::string& path, const Shape& shape, const T* data);
  template <class T>
  void write_dataset(const std::string& path, const Shape& shape, const std::vector<T>& data);
  Shape dataset_shape(const std::string& path) const;
  // Reads a whole dataset, which must hold numbers of T's kind (integer or floating point) and
  // have shape `expected`.
  template <class T>
  std::vector<T> read_dataset(const std::string& path, const Shape& expected) const;

  // Attributes of this group; writing one replaces an attribute of that name.
  bool has_attribute(const std::string& name) const;
  void write_attribute(const std::string& name, const std::string& value);
  void write_attribute(const std::string& name, const char* value);
  void write_attribute(const std::string& name, double value);
  void write_attribute(const std::string& name, std::int64_t value);
  void write_attribute(const std::string& name, const std::vector<double>& values);
  void write_attribute(const std::string& name, const std::vector<std::string>& values);
  std::string read_string_attribute(const std::string& name) const;
  double read_double_attribute(const std::string& name) const;
  std::int64_t read_int64_attribute(const std::string& name) const;
  std::vector<double> read_doubles_attribute(const std::string& name) const;
  std::vector<std::string> read_strings_attribute(const std::string& name) const;

 protected:
  Group(Handle handle, std::shared_ptr<const std::string> label, std::string path)
      : handle_(std::move(handle)), label_(std::move(label)), path_(std::move(path)) {}

  // "<label>: <what> <absolute object path>: <problem>".
  // Reading found `path` unusable (UnusableFileError), or writing it failed (romp::Error).
  [[noreturn]] void fail(const std::string& what, const std::string& path, const std::string& problem) const;
  [[noreturn]] void fail_to_write(const std::string& what, const std::string& path, const std::string& problem) const;
  std::string absolute(const std::string& path) const;

  Handle handle_;
  std::shared_ptr<const std::string> label_;
  std::string path_;
};

enum class Mode { ReadOnly, ReadWrite };

// Files are opened without HDF5's file locks (HDF5_USE_FILE_LOCKING=FALSE): romp writes a file from
// one place and publishes it by renaming, while a held lock would keep ParaView out of a running
// snapshot, fail on file systems without locks, and fail when one process opens a file twice with
// different lock settings. Calls from several threads are serialised inside romp_io.
class File : public Group {
 public:
  // A new, empty file at `path` (an existing one is replaced). `role` names the file's kind in
  // messages ("snapshot", "checkpoint", "model").
  static File create(const std::string& path, const std::string& role);
  static File open(const std::string& path, Mode mode, const std::string& role);

  const std::string& filename() const { return filename_; }
  // Writes everything cached to the file, so a crash afterwards leaves it readable.
  void flush();
  // Closes now, reporting a failed final write as an error (the destructor closes silently).
  void close();

 private:
  File(Handle handle, std::shared_ptr<const std::string> label, std::string filename)
      : Group(std::move(handle), std::move(label), "/"), filename_(std::move(filename)) {}

  std::string filename_;
};

extern template void Group::write_dataset(const std::string&, const Shape&, const float*);
extern template void Group::write_dataset(const std::string&, const Shape&, const double*);
extern template void Group::write_dataset(const std::string&, const Shape&, const std::int32_t*);
extern template void Group::write_dataset(const std::string&, const Shape&, const std::int64_t*);
extern template std::vector<float> Group::read_dataset(const std::string&, const Shape&) const;
extern template std::vector<double> Group::read_dataset(const std::string&, const Shape&) const;
extern template std::vector<std::int32_t> Group::read_dataset(const std::string&, const Shape&) const;
extern template std::vector<std::int64_t> Group::read_dataset(const std::string&, const Shape&) const;

template <class T>
void Group::write_dataset(const std::string& path, const Shape& shape, const std::vector<T>& data) {
  static_assert(kIsElement<T>, "datasets hold float, double, int32 or int64");
  std::uint64_t count = 1;
  for (std::uint64_t extent : shape) count *= extent;
  if (count != data.size()) {
    fail("dataset", path, "shape holds " + std::to_string(count) + " elements, data " + std::to_string(data.size()));
  }
  write_dataset(path, shape, data.data());
}

}  // namespace romp::io::hdf5
