// HDF5 C API calls behind romp's file wrapper: every call is serialised, HDF5's own error printing is
// off, and a failed call becomes a romp::Error with HDF5's innermost reason.
#include "nn/io/hdf5_file.h"

#include <hdf5.h>

#include <algorithm>
#include <filesystem>
#include <mutex>
#include <optional>

#include "kernels/core/error.h"

namespace romp::io::hdf5 {

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

// Strings are written fixed-length, padded with NULs: they then live in the attribute's object header,
// which the files' format keeps under a checksum (file_creation_access). Variable-length strings live in
// the global heap, which has none: a damaged byte there crashed libhdf5 inside H5Aread (H5HG_read).
Handle fixed_string_type(std::size_t longest) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.id(), std::max<std::size_t>(longest, 1));
  H5Tset_strpad(type.id(), H5T_STR_NULLPAD);
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

// New files in the HDF5 1.8 format: its superblock, object headers and attribute storage carry checksums,
// so damaged metadata there is an error where the earliest format (the library's default) read it as it
// came. Not the 1.10 format, whose chunk indexes are checksummed too: its superblock marks a file open
// for writing, and a run killed mid-write would leave a partial output that no longer opens. Chunk
// indexes stay unchecked B-trees. HDF5 1.8 and later read it (h5py, ParaView).
Handle file_creation_access() {
  Handle list = file_access();
  H5Pset_libver_bounds(list.id(), H5F_LIBVER_V18, H5F_LIBVER_V18);
  return list;
}

// Datasets are stored in chunks of at most this many bytes, each with a Fletcher-32 checksum that every
// read verifies: damaged data is an error, not a result (a resumed run used to carry it on).
constexpr std::uint64_t kChunkBytes = std::uint64_t(64) << 20;

Handle checksummed_dataset_creation(const std::vector<hsize_t>& dims, std::size_t element_bytes) {
  Handle list(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  std::vector<hsize_t> chunk(dims);
  std::uint64_t bytes = element_bytes;
  for (const hsize_t extent : chunk) bytes *= extent;
  for (std::size_t axis = 0; axis < chunk.size() && bytes > kChunkBytes; ++axis) {
    while (chunk[axis] > 1 && bytes > kChunkBytes) {
      bytes = bytes / chunk[axis] * ((chunk[axis] + 1) / 2);
      chunk[axis] = (chunk[axis] + 1) / 2;
    }
  }
  H5Pset_chunk(list.id(), int(chunk.size()), chunk.data());
  H5Pset_fletcher32(list.id());
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
  // The padding the type declares: NULs (romp's), or spaces (Fortran's).
  const std::string padding = H5Tget_strpad(type) == H5T_STR_SPACEPAD ? std::string(" ") : std::string(1, '\0');
  for (std::uint64_t i = 0; i < count; ++i) {
    std::string value = buffer.substr(i * size, size);
    const std::size_t end = value.find_last_not_of(padding);
    value.erase(end == std::string::npos ? 0 : end + 1);
    // A NUL-terminated string ends at its first NUL.
    value.erase(std::min(value.size(), value.find('\0')));
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
  throw UnusableFileError(label() + ": " + what + " " + absolute(path) + ": " + problem);
}

void Group::fail_to_write(const std::string& what, const std::string& path, const std::string& problem) const {
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
  if (exists(path)) fail_to_write("group", path, "already exists");
  Handle links = link_creation_with_parents();
  Handle group(H5Gcreate2(handle_.id(), path.c_str(), links.id(), H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
  if (!group.valid()) fail_to_write("group", path, "cannot create: " + library_reason());
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
    fail_to_write("object", path, "cannot remove: " + library_reason());
  }
}

template <class T>
void Group::write_dataset(const std::string& path, const Shape& shape, const T* data) {
  static_assert(kIsElement<T>, "datasets hold float, double, int32 or int64");
  LibraryCall call;
  if (exists(path)) fail_to_write("dataset", path, "already exists");
  const std::vector<hsize_t> dims(shape.begin(), shape.end());
  Handle space(shape.empty() ? H5Screate(H5S_SCALAR) : H5Screate_simple(int(dims.size()), dims.data(), nullptr),
               H5Sclose);
  if (!space.valid())
    fail_to_write("dataset", path, "cannot describe shape " + describe(shape) + ": " + library_reason());
  Handle links = link_creation_with_parents();
  // Chunked with a checksum where there is data to chunk (a scalar or an empty dataset has none).
  const bool chunked = !dims.empty() && point_count(space.id()) > 0;
  Handle creation = chunked ? checksummed_dataset_creation(dims, sizeof(T)) : Handle();
  Handle dataset(H5Dcreate2(handle_.id(), path.c_str(), file_type<T>(), space.id(), links.id(),
                            chunked ? creation.id() : H5P_DEFAULT, H5P_DEFAULT),
                 H5Dclose);
  if (!dataset.valid()) fail_to_write("dataset", path, "cannot create: " + library_reason());
  if (point_count(space.id()) > 0 &&
      H5Dwrite(dataset.id(), memory_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0) {
    fail_to_write("dataset", path, "cannot write: " + library_reason());
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

namespace {

// What is wrong with the records of a chunked dataset's stored chunks, or "" when each holds the bytes its
// filters give for one chunk of `chunk` elements of `element_size` bytes: exactly that (plus the 4-byte
// checksum where Fletcher-32 applied) when the pipeline has no other filter, at least the checksum otherwise.
// libhdf5 1.10's Fletcher-32 filter reads size − 4 bytes of a chunk stored in fewer than 4 (the model fuzzer:
// a SEGV in H5_checksum_fletcher32 from a damaged chunk record), so the records are checked before reading.
std::string chunk_record_problem(hid_t dataset, hid_t creation, const std::vector<hsize_t>& chunk,
                                 std::size_t element_size) {
  bool checksummed = false, other_filters = false;
  int checksum_bit = 0;
  const int filters = H5Pget_nfilters(creation);
  for (int k = 0; k < filters; ++k) {
    unsigned flags = 0;
    std::size_t values = 0;
    const H5Z_filter_t filter = H5Pget_filter2(creation, unsigned(k), &flags, &values, nullptr, 0, nullptr, nullptr);
    if (filter == H5Z_FILTER_FLETCHER32) {
      checksummed = true;
      checksum_bit = k;
    } else {
      other_filters = true;
    }
  }
  hsize_t chunk_bytes = element_size;
  for (hsize_t extent : chunk) chunk_bytes *= extent;
  // libhdf5 1.10 takes the dataset's own dataspace here (H5S_ALL fails).
  Handle space(H5Dget_space(dataset), H5Sclose);
  hsize_t chunks = 0;
  if (!space.valid() || H5Dget_num_chunks(dataset, space.id(), &chunks) < 0) return "its chunk index is unreadable";
  // romp's chunks hold up to 64 MiB (a few per dataset); libhdf5 finds a chunk's record by walking the index
  // from the start, so a file of millions of tiny chunks would take hours to check.
  constexpr hsize_t kMostChunks = 4096;
  if (chunks > kMostChunks)
    return std::to_string(chunks) + " chunks; romp reads at most " + std::to_string(kMostChunks);
  std::vector<hsize_t> offset(chunk.size());
  for (hsize_t index = 0; index < chunks; ++index) {
    unsigned skipped = 0;
    haddr_t address = 0;
    hsize_t size = 0;
    if (H5Dget_chunk_info(dataset, space.id(), index, offset.data(), &skipped, &address, &size) < 0)
      return "chunk " + std::to_string(index) + "'s record is unreadable";
    const bool has_checksum = checksummed && (skipped & (1u << checksum_bit)) == 0;
    const hsize_t checksum = has_checksum ? 4 : 0;
    if (other_filters ? size < checksum : size != chunk_bytes + checksum) {
      return "chunk " + std::to_string(index) + " is stored in " + std::to_string(size) + " bytes, expected " +
             (other_filters ? "at least " + std::to_string(checksum) : std::to_string(chunk_bytes + checksum));
    }
  }
  return "";
}

}  // namespace

template <class T>
std::vector<T> Group::read_dataset(const std::string& path, const Shape& expected) const {
  static_assert(kIsElement<T>, "datasets hold float, double, int32 or int64");
  LibraryCall call;
  const Shape shape = dataset_shape(path);
  Handle dataset(H5Dopen2(handle_.id(), path.c_str(), H5P_DEFAULT), H5Dclose);
  Handle type(H5Dget_type(dataset.id()), H5Tclose);
  const H5T_class_t stored = H5Tget_class(type.id());
  if (stored != element_class<T>()) {
    fail("dataset", path,
         std::string("holds ") + describe_class(stored) + ", expected " + describe_class(element_class<T>()));
  }
  if (shape != expected) fail("dataset", path, "shape " + describe(shape) + ", expected " + describe(expected));
  std::uint64_t count = 1;
  for (std::uint64_t extent : shape) count *= extent;
  // What HDF5 would allocate to read it must fit what the shape holds: a damaged chunk size or layout
  // made libhdf5 allocate 4 GB for a dataset of a few bytes (the snapshot fuzzer, tests/fuzz).
  const std::uint64_t bytes = count * sizeof(T);
  if (count > 0) {
    Handle creation(H5Dget_create_plist(dataset.id()), H5Pclose);
    if (H5Pget_layout(creation.id()) == H5D_CHUNKED) {
      std::vector<hsize_t> chunk(shape.size());
      if (H5Pget_chunk(creation.id(), int(chunk.size()), chunk.data()) != int(chunk.size()))
        fail("dataset", path, "its chunk shape is unreadable: damaged");
      for (std::size_t axis = 0; axis < chunk.size(); ++axis) {
        if (chunk[axis] == 0 || chunk[axis] > std::max<hsize_t>(shape[axis], 1)) {
          fail("dataset", path,
               "chunk shape " + describe(Shape(chunk.begin(), chunk.end())) + " exceeds shape " + describe(shape) +
                   ": damaged");
        }
      }
      const std::string problem = chunk_record_problem(dataset.id(), creation.id(), chunk, H5Tget_size(type.id()));
      if (!problem.empty()) fail("dataset", path, problem + ": damaged");
    }
    const hsize_t stored = H5Dget_storage_size(dataset.id());
    if (stored > 2 * bytes + (std::uint64_t(1) << 20))
      fail("dataset", path,
           std::to_string(stored) + " bytes stored for " + std::to_string(bytes) + " of data: damaged");
  }
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
  Handle type = fixed_string_type(value.size());
  const std::string text = value.empty() ? std::string(1, '\0') : value;
  if (!write_attribute_data(handle_.id(), name, type.id(), type.id(), {}, text.data())) {
    fail_to_write("attribute", name, "cannot write: " + library_reason());
  }
}

void Group::write_attribute(const std::string& name, const char* value) { write_attribute(name, std::string(value)); }

void Group::write_attribute(const std::string& name, double value) {
  LibraryCall call;
  if (!write_attribute_data(handle_.id(), name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {}, &value)) {
    fail_to_write("attribute", name, "cannot write: " + library_reason());
  }
}

void Group::write_attribute(const std::string& name, std::int64_t value) {
  LibraryCall call;
  if (!write_attribute_data(handle_.id(), name, H5T_STD_I64LE, H5T_NATIVE_INT64, {}, &value)) {
    fail_to_write("attribute", name, "cannot write: " + library_reason());
  }
}

void Group::write_attribute(const std::string& name, const std::vector<double>& values) {
  LibraryCall call;
  if (!write_attribute_data(handle_.id(), name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {hsize_t(values.size())},
                            values.data())) {
    fail_to_write("attribute", name, "cannot write: " + library_reason());
  }
}

void Group::write_attribute(const std::string& name, const std::vector<std::string>& values) {
  LibraryCall call;
  std::size_t longest = 1;
  for (const std::string& value : values) longest = std::max(longest, value.size());
  Handle type = fixed_string_type(longest);
  std::string texts(longest * values.size(), '\0');
  for (std::size_t i = 0; i < values.size(); ++i) texts.replace(i * longest, values[i].size(), values[i]);
  if (!write_attribute_data(handle_.id(), name, type.id(), type.id(), {hsize_t(values.size())}, texts.data())) {
    fail_to_write("attribute", name, "cannot write: " + library_reason());
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
  Handle access = file_creation_access();
  Handle file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.id()), H5Fclose);
  if (!file.valid()) throw Error(*label + ": cannot create: " + library_reason());
  return File(std::move(file), std::move(label), path);
}

File File::open(const std::string& path, Mode mode, const std::string& role) {
  LibraryCall call;
  auto label = std::make_shared<const std::string>(role + " " + path);
  std::error_code error;
  if (!std::filesystem::exists(path, error)) throw UnusableFileError(*label + ": no such file");
  if (!std::filesystem::is_regular_file(path, error)) throw UnusableFileError(*label + ": not a regular file");
  Handle access = file_access();
  Handle file(H5Fopen(path.c_str(), mode == Mode::ReadOnly ? H5F_ACC_RDONLY : H5F_ACC_RDWR, access.id()), H5Fclose);
  if (!file.valid()) throw UnusableFileError(*label + ": cannot open as HDF5: " + library_reason());
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

}  // namespace romp::io::hdf5
