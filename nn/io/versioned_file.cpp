// Format checks on opening and the atomic write of versioned HDF5 files.
#include "nn/io/versioned_file.h"

#include <fmt/format.h>

#include "nn/io/atomic_file.h"

namespace romp::io {

hdf5::File open_versioned_file(const std::string& path, const FileFormat& format) {
  hdf5::File file = hdf5::File::open(path, hdf5::Mode::ReadOnly, format.role);
  if (!file.has_attribute("format")) {
    throw UnusableFileError(
        fmt::format("{}: not {}: root attribute format is missing", file.label(), format.description));
  }
  const std::string name = file.read_string_attribute("format");
  if (name != format.name) {
    throw UnusableFileError(fmt::format("{}: not {}: root attribute format is \"{}\", expected \"{}\"", file.label(),
                                        format.description, name, format.name));
  }
  const std::int64_t version = file.read_int64_attribute("format_version");
  if (version < 1 || version > format.version) {
    throw UnusableFileError(fmt::format("{}: format_version {} is not one this romp reads (1 .. {}){}", file.label(),
                                        version, format.version,
                                        version > format.version ? "; a newer romp wrote it" : ""));
  }
  return file;
}

void write_format_attributes(hdf5::File& file, const FileFormat& format) {
  file.write_attribute("format", format.name);
  file.write_attribute("format_version", format.version);
}

void write_versioned_file(const std::string& path, const FileFormat& format,
                          const std::function<void(hdf5::File&)>& fill) {
  AtomicFile target(path);
  {
    hdf5::File file = hdf5::File::create(target.temp_path(), format.role);
    write_format_attributes(file, format);
    fill(file);
    file.close();
  }
  target.commit();
}

}  // namespace romp::io
