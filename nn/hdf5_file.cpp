// HDF5 C API calls behind romp's file wrapper: every call is serialised, HDF5's own error printing is
// off, and a failed call becomes a romp::Error with HDF5's innermost reason.
#include "nn/hdf5_file.h"

#include <hdf5.h>

#include <algorithm>
#include <filesystem>
#include <mutex>
#include <optional>

#include "kernels/core/error.h"

namespace romp::hdf5 {

static_assert(std::is_same_v<hid_t, std::int64_t> && std::is_same_v<herr_t, int>,
              "Handle stores identifiers as int64 and closers as int(int64), as in HDF5 >= 1.10");

namespace {

// HDF5 is only safe across threads when built with --enable-threadsafe; the I/O worker and a
// reader on another thread must not meet inside the library otherwise.
std::recursive_mutex& library_mutex() {
  static std::recursive_mutex mutex;
  return mutex;
}

// Held around every library call. Threadsafe builds keep one error stack (and its auto-printing
// setting) per thread, so printing is switched off on each thread that calls in.
class LibraryCall {
 public:
  LibraryCall() : lock_(library_mutex()) {
    thread_local bool printing_off = false;
    if (!printing_off) {
      H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
      printing_off = true;
    }
    H5Eclear2(H5E_DEFAULT);
  }

 private:
  std::lock_guard<std::recursive_mutex> lock_;
};

// The description of the innermost error on this thread's stack: where HDF5 found the problem
// ("file signature not found", "truncated file: eof = ...").
std::string library_reason() {
  std::string reason;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_UPWARD,
      [](unsigned depth, const H5E_error2_t* error, void* out) -> herr_t {
        if (depth == 0 && error->desc != nullptr) *static_cast<std::string*>(out) = error->desc;
        return 0;
      },
      &reason);
  H5Eclear2(H5E_DEFAULT);
  return reason.empty() ? std::string("the HDF5 library reported a failure") : reason;
}

std::string describe(const Shape& shape) {
  std::string text = "[";
  for (std::size_t i = 0; i < shape.size(); ++i) text += (i ? ", " : "") + std::to_string(shape[i]);
  return text + "]";
}

const char* describe_class(H5T_class_t type_class) {
  switch (type_class) {
    case H5T_INTEGER: return "integers";
    case H5T_FLOAT: return "floating-point numbers";
    case H5T_STRING: return "strings";
    default: return "values that are neither numbers nor strings";
  }
}

template <class T>
hid_t memory_type() {
  if constexpr (std::is_same_v<T, float>) return H5T_NATIVE_FLOAT;
  if constexpr (std::is_same_v<T, double>) return H5T_NATIVE_DOUBLE;
  if constexpr (std::is_same_v<T, std::int32_t>) return H5T_NATIVE_INT32;
  if constexpr (std::is_same_v<T, std::int64_t>) return H5T_NATIVE_INT64;
}

// Files are little-endian whatever the host, as every reader of romp files expects.
template <class T>
hid_t file_type() {
  if constexpr (std::is_same_v<T, float>) return H5T_IEEE_F32LE;
  if constexpr (std::is_same_v<T, double>) return H5T_IEEE_F64LE;
  if constexpr (std::is_same_v<T, std::int32_t>) return H5T_STD_I32LE;
  if constexpr (std::is_same_v<T, std::int64_t>) return H5T_STD_I64LE;
}

template <class T>
H5T_class_t element_class() {
  return std::is_floating_point_v<T> ? H5T_FLOAT : H5T_INTEGER;
}

// Element count of a dataspace: 0 for a null space, 1 for a scalar.
std::uint64_t point_count(hid_t space) {
  switch (H5Sget_simple_extent_type(space)) {
    case H5S_NULL: return 0;
    case H5S_SCALAR: return 1;
    default: return std::uint64_t(H5Sget_simple_extent_npoints(space));
  }
}

Handle variable_string_type() {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.id(), H5T_VARIABLE);
  H5Tset_cset(type.id(), H5T_CSET_UTF8);
  return type;
}

Handle link_creation_with_parents() {
  Handle list(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  H5Pset_create_intermediate_group(list.id(), 1);
  return list;
}

Handle file_access() {
  Handle list(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  H5Pset_file_locking(list.id(), false, true);
  return list;
}

// Strings as written: variable-length ones are copied and freed, fixed-length ones lose their
// padding. Nothing when HDF5 cannot read them.
std::optional<std::vector<std::string>> read_strings(hid_t attribute, hid_t type, std::uint64_t count) {
  std::vector<std::string> values;
  values.reserve(count);
  if (H5Tis_variable_str(type) > 0) {
    std::vector<char*> pointers(count, nullptr);
    if (count > 0 && H5Aread(attribute, type, pointers.data()) < 0) return std::nullopt;
    for (char* pointer : pointers) {
      values.emplace_back(pointer != nullptr ? pointer : "");
      H5free_memory(pointer);
    }
    return values;
  }
  const std::size_t size = H5Tget_size(type);
  std::string buffer(size * count, '\0');
  if (count > 0 && H5Aread(attribute, type, buffer.data()) < 0) return std::nullopt;
  for (std::uint64_t i = 0; i < count; ++i) {
    std::string value = buffer.substr(i * size, size);
    value.erase(value.find_last_not_of(std::string("\0 ", 2)) + 1);
    values.push_back(std::move(value));
  }
  return values;
}

}  // namespace

Handle::Handle(Handle&& other) noexcept : id_(other.id_), closer_(other.closer_) { other.id_ = -1; }

Handle& Handle::operator=(Handle&& other) noexcept {
  if (this != &other) {
    close();
    id_ = other.id_;
    closer_ = other.closer_;
    other.id_ = -1;
  }
  return *this;
}

Handle::~Handle() { close(); }

bool Handle::close() {
  if (id_ < 0) return true;
  LibraryCall call;
  const bool closed = closer_(id_) >= 0;
  id_ = -1;
  return closed;
}

std::string Group::absolute(const std::string& path) const {
  if (!path.empty() && path.front() == '/') return path;
  return path_ == "/" ? "/" + path : path_ + "/" + path;
}

void Group::fail(const std::string& what, const std::string& path, const std::string& problem) const {
  throw Error(label() + ": " + what + " " + absolute(path) + ": " + problem);
}

bool Group::exists(const std::string& path) const {
  LibraryCall call;
  if (path == "/" || path == ".") return true;
  // H5Lexists fails (rather than answering no) when an intermediate link is missing, so walk down.
  for (std::size_t end = path.find('/', 1);; end = path.find('/', end + 1)) {
    const std::string prefix = path.substr(0, end);
    if (H5Lexists(handle_.id(), prefix.c_str(), H5P_DEFAULT) <= 0) {
      H5Eclear2(H5E_DEFAULT);
      return false;
    }
    if (end == std::string::npos) break;
  }
  const htri_t resolves = H5Oexists_by_name(handle_.id(), path.c_str(), H5P_DEFAULT);
  H5Eclear2(H5E_DEFAULT);
  return resolves > 0;
}

namespace {

H5I_type_t object_type(hid_t location, const std::string& path) {
  Handle object(H5Oopen(location, path.c_str(), H5P_DEFAULT), H5Oclose);
  if (!object.valid()) return H5I_BADID;
  return H5Iget_type(object.id());
}

}  // namespace

bool Group::is_group(const std::string& path) const {
  LibraryCall call;
  return exists(path) && object_type(handle_.id(), path) == H5I_GROUP;
}

bool Group::is_dataset(const std::string& path) const {
  LibraryCall call;
  return exists(path) && object_type(handle_.id(), path) == H5I_DATASET;
}

Group Group::open_group(const std::string& path) const {
  LibraryCall call;
  if (!exists(path)) fail("group", path, "missing");
  if (!is_group(path)) fail("group", path, "is not a group");
  Handle group(H5Gopen2(handle_.id(), path.c_str(), H5P_DEFAULT), H5Gclose);
  if (!group.valid()) fail("group", path, library_reason());
  return Group(std::move(group), label_, absolute(path));
}

Group Group::create_group(const std::string& path) {
  LibraryCall call;
  if (exists(path)) fail("group", path, "already exists");
  Handle links = link_creation_with_parents();
  Handle group(H5Gcreate2(handle_.id(), path.c_str(), links.id(), H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
  if (!group.valid()) fail("group", path, "cannot create: " + library_reason());
  return Group(std::move(group), label_, absolute(path));
}

std::vector<std::string> Group::list() const {
  LibraryCall call;
  H5G_info_t info;
  if (H5Gget_info(handle_.id(), &info) < 0) fail("group", path_, library_reason());
  std::vector<std::string> names;
  names.reserve(info.nlinks);
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    const ssize_t length =
        H5Lget_name_by_idx(handle_.id(), ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    if (length < 0) fail("group", path_, library_reason());
    std::string name(std::size_t(length) + 1, '\0');
    H5Lget_name_by_idx(handle_.id(), ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), name.size(), H5P_DEFAULT);
    name.resize(std::size_t(length));
    names.push_back(std::move(name));
  }
  return names;
}

void Group::remove(const std::string& path) {
  LibraryCall call;
  if (!exists(path)) fail("object", path, "missing");
  if (H5Ldelete(handle_.id(), path.c_str(), H5P_DEFAULT) < 0) {
    fail("object", path, "cannot remove: " + library_reason());
  }
}

template <class T>
void Group::write_dataset(const std::string& path, const Shape& shape, const T* data) {
  static_assert(kIsElement<T>, "datasets hold float, double, int32 or int64");
  LibraryCall call;
  if (exists(path)) fail("dataset", path, "already exists");
  const std::vector<hsize_t> dims(shape.begin(), shape.end());
  Handle space(shape.empty() ? H5Screate(H5S_SCALAR) : H5Screate_simple(int(dims.size()), dims.data(), nullptr),
               H5Sclose);
  if (!space.valid()) fail("dataset", path, "cannot describe shape " + describe(shape) + ": " + library_reason());
  Handle links = link_creation_with_parents();
  Handle dataset(
      H5Dcreate2(handle_.id(), path.c_str(), file_type<T>(), space.id(), links.id(), H5P_DEFAULT, H5P_DEFAULT),
      H5Dclose);
  if (!dataset.valid()) fail("dataset", path, "cannot create: " + library_reason());
  if (point_count(space.id()) > 0 &&
      H5Dwrite(dataset.id(), memory_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0) {
    fail("dataset", path, "cannot write: " + library_reason());
  }
}

Shape Group::dataset_shape(const std::string& path) const {
  LibraryCall call;
  if (!exists(path)) fail("dataset", path, "missing");
  if (!is_dataset(path)) fail("dataset", path, "is not a dataset");
  Handle dataset(H5Dopen2(handle_.id(), path.c_str(), H5P_DEFAULT), H5Dclose);
  Handle space(H5Dget_space(dataset.id()), H5Sclose);
  if (!space.valid()) fail("dataset", path, library_reason());
  std::vector<hsize_t> dims(std::size_t(std::max(0, H5Sget_simple_extent_ndims(space.id()))));
  H5Sget_simple_extent_dims(space.id(), dims.data(), nullptr);
  return Shape(dims.begin(), dims.end());
}

template <class T>
std::vector<T> Group::read_dataset(const std::string& path, const Shape& expected) const {
  static_assert(kIsElement<T>, "datasets hold float, double, int32 or int64");
  LibraryCall call;
  const Shape shape = dataset_shape(path);
  Handle dataset(H5Dopen2(handle_.id(), path.c_str(), H5P_DEFAULT), H5Dclose);
  Handle type(H5Dget_type(dataset.id()), H5Tclose);
  const H5T_class_t stored = H5Tget_class(type.id());
  if (stored != element_class<T>()) {
    fail("dataset", path, std::string("holds ") + describe_class(stored) + ", expected " +
                              describe_class(element_class<T>()));
  }
  if (shape != expected) fail("dataset", path, "shape " + describe(shape) + ", expected " + describe(expected));
  std::uint64_t count = 1;
  for (std::uint64_t extent : shape) count *= extent;
  std::vector<T> values(count);
  if (count > 0 && H5Dread(dataset.id(), memory_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0) {
    fail("dataset", path, "cannot read: " + library_reason());
  }
  return values;
}

template void Group::write_dataset(const std::string&, const Shape&, const float*);
template void Group::write_dataset(const std::string&, const Shape&, const double*);
template void Group::write_dataset(const std::string&, const Shape&, const std::int32_t*);
template void Group::write_dataset(const std::string&, const Shape&, const std::int64_t*);
template std::vector<float> Group::read_dataset(const std::string&, const Shape&) const;
template std::vector<double> Group::read_dataset(const std::string&, const Shape&) const;
template std::vector<std::int32_t> Group::read_dataset(const std::string&, const Shape&) const;
template std::vector<std::int64_t> Group::read_dataset(const std::string&, const Shape&) const;

bool Group::has_attribute(const std::string& name) const {
  LibraryCall call;
  const htri_t found = H5Aexists(handle_.id(), name.c_str());
  if (found < 0) fail("attribute", name, library_reason());
  return found > 0;
}

namespace {

// Creates attribute `name` on `location` (replacing one of that name) and writes `data` into it.
bool write_attribute_data(hid_t location, const std::string& name, hid_t file_type, hid_t memory_type,
                          const std::vector<hsize_t>& dims, const void* data) {
  if (H5Aexists(location, name.c_str()) > 0 && H5Adelete(location, name.c_str()) < 0) return false;
  Handle space(dims.empty() ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, dims.data(), nullptr), H5Sclose);
  Handle attribute(H5Acreate2(location, name.c_str(), file_type, space.id(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!attribute.valid()) return false;
  return point_count(space.id()) == 0 || H5Awrite(attribute.id(), memory_type, data) >= 0;
}

}  // namespace

void Group::write_attribute(const std::string& name, const std::string& value) {
  LibraryCall call;
  Handle type = variable_string_type();
  const char* text = value.c_str();
  if (!write_attribute_data(handle_.id(), name, type.id(), type.id(), {}, &text)) {
    fail("attribute", name, "cannot write: " + library_reason());
  }
}

void Group::write_attribute(const std::string& name, const char* value) { write_attribute(name, std::string(value)); }

void Group::write_attribute(const std::string& name, double value) {
  LibraryCall call;
  if (!write_attribute_data(handle_.id(), name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {}, &value)) {
    fail("attribute", name, "cannot write: " + library_reason());
  }
}

void Group::write_attribute(const std::string& name, std::int64_t value) {
  LibraryCall call;
  if (!write_attribute_data(handle_.id(), name, H5T_STD_I64LE, H5T_NATIVE_INT64, {}, &value)) {
    fail("attribute", name, "cannot write: " + library_reason());
  }
}

void Group::write_attribute(const std::string& name, const std::vector<double>& values) {
  LibraryCall call;
  if (!write_attribute_data(handle_.id(), name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {hsize_t(values.size())},
                            values.data())) {
    fail("attribute", name, "cannot write: " + library_reason());
  }
}

void Group::write_attribute(const std::string& name, const std::vector<std::string>& values) {
  LibraryCall call;
  Handle type = variable_string_type();
  std::vector<const char*> texts;
  texts.reserve(values.size());
  for (const std::string& value : values) texts.push_back(value.c_str());
  if (!write_attribute_data(handle_.id(), name, type.id(), type.id(), {hsize_t(values.size())}, texts.data())) {
    fail("attribute", name, "cannot write: " + library_reason());
  }
}

namespace {

// An open attribute, its stored type and its element count; `problem` says why opening failed.
struct OpenAttribute {
  Handle attribute, type;
  std::uint64_t count = 0;
  H5T_class_t type_class = H5T_NO_CLASS;
  std::string problem;
};

OpenAttribute open_attribute(hid_t location, const std::string& name) {
  OpenAttribute open;
  if (H5Aexists(location, name.c_str()) <= 0) {
    open.problem = "missing";
    return open;
  }
  open.attribute = Handle(H5Aopen(location, name.c_str(), H5P_DEFAULT), H5Aclose);
  open.type = Handle(H5Aget_type(open.attribute.id()), H5Tclose);
  Handle space(H5Aget_space(open.attribute.id()), H5Sclose);
  if (!open.attribute.valid() || !open.type.valid() || !space.valid()) {
    open.problem = library_reason();
    return open;
  }
  open.count = point_count(space.id());
  open.type_class = H5Tget_class(open.type.id());
  return open;
}

}  // namespace

std::vector<std::string> Group::read_strings_attribute(const std::string& name) const {
  LibraryCall call;
  const OpenAttribute open = open_attribute(handle_.id(), name);
  if (!open.problem.empty()) fail("attribute", name, open.problem);
  if (open.type_class != H5T_STRING) {
    fail("attribute", name, std::string("holds ") + describe_class(open.type_class) + ", expected strings");
  }
  std::optional<std::vector<std::string>> values = read_strings(open.attribute.id(), open.type.id(), open.count);
  if (!values) fail("attribute", name, "cannot read: " + library_reason());
  return std::move(*values);
}

std::string Group::read_string_attribute(const std::string& name) const {
  const std::vector<std::string> values = read_strings_attribute(name);
  if (values.size() != 1) fail("attribute", name, std::to_string(values.size()) + " strings, expected one");
  return values.front();
}

std::vector<double> Group::read_doubles_attribute(const std::string& name) const {
  LibraryCall call;
  const OpenAttribute open = open_attribute(handle_.id(), name);
  if (!open.problem.empty()) fail("attribute", name, open.problem);
  if (open.type_class != H5T_FLOAT && open.type_class != H5T_INTEGER) {
    fail("attribute", name, std::string("holds ") + describe_class(open.type_class) + ", expected numbers");
  }
  std::vector<double> values(open.count);
  if (!values.empty() && H5Aread(open.attribute.id(), H5T_NATIVE_DOUBLE, values.data()) < 0) {
    fail("attribute", name, "cannot read: " + library_reason());
  }
  return values;
}

double Group::read_double_attribute(const std::string& name) const {
  const std::vector<double> values = read_doubles_attribute(name);
  if (values.size() != 1) fail("attribute", name, std::to_string(values.size()) + " numbers, expected one");
  return values.front();
}

std::int64_t Group::read_int64_attribute(const std::string& name) const {
  LibraryCall call;
  const OpenAttribute open = open_attribute(handle_.id(), name);
  if (!open.problem.empty()) fail("attribute", name, open.problem);
  if (open.type_class != H5T_INTEGER) {
    fail("attribute", name, std::string("holds ") + describe_class(open.type_class) + ", expected an integer");
  }
  if (open.count != 1) fail("attribute", name, std::to_string(open.count) + " integers, expected one");
  std::int64_t value = 0;
  if (H5Aread(open.attribute.id(), H5T_NATIVE_INT64, &value) < 0) {
    fail("attribute", name, "cannot read: " + library_reason());
  }
  return value;
}

File File::create(const std::string& path, const std::string& role) {
  LibraryCall call;
  auto label = std::make_shared<const std::string>(role + " " + path);
  Handle access = file_access();
  Handle file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.id()), H5Fclose);
  if (!file.valid()) throw Error(*label + ": cannot create: " + library_reason());
  return File(std::move(file), std::move(label), path);
}

File File::open(const std::string& path, Mode mode, const std::string& role) {
  LibraryCall call;
  auto label = std::make_shared<const std::string>(role + " " + path);
  std::error_code error;
  if (!std::filesystem::exists(path, error)) throw Error(*label + ": no such file");
  if (!std::filesystem::is_regular_file(path, error)) throw Error(*label + ": not a regular file");
  Handle access = file_access();
  Handle file(H5Fopen(path.c_str(), mode == Mode::ReadOnly ? H5F_ACC_RDONLY : H5F_ACC_RDWR, access.id()), H5Fclose);
  if (!file.valid()) throw Error(*label + ": cannot open as HDF5: " + library_reason());
  return File(std::move(file), std::move(label), path);
}

void File::flush() {
  LibraryCall call;
  if (H5Fflush(handle_.id(), H5F_SCOPE_LOCAL) < 0) throw Error(label() + ": cannot flush: " + library_reason());
}

void File::close() {
  LibraryCall call;
  if (!handle_.close()) throw Error(label() + ": cannot close: " + library_reason());
}

}  // namespace romp::hdf5
