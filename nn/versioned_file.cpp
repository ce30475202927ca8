// Format checks on opening and the partial-then-rename write of versioned HDF5 files.
#include "nn/versioned_file.h"

#include <fmt/format.h>

#include <filesystem>
#include <system_error>

#include "kernels/core/error.h"

namespace romp::nn {

hdf5::File open_versioned_file(const std::string& path, const FileFormat& format) {
  hdf5::File file = hdf5::File::open(path, hdf5::Mode::ReadOnly, format.role);
  if (!file.has_attribute("format") || file.read_string_attribute("format") != format.name) {
    throw hdf5::UnusableFileError(fmt::format("{}: not {}: root attribute format is not \"{}\"", file.label(),
                                              format.description, format.name));
  }
  const std::int64_t version = file.read_int64_attribute("format_version");
  if (version < 1 || version > format.version) {
    throw hdf5::UnusableFileError(fmt::format("{}: format_version {} is not one this romp reads (1 .. {})",
                                              file.label(), version, format.version));
  }
  return file;
}

void write_versioned_file(const std::string& path, const FileFormat& format,
                          const std::function<void(hdf5::File&)>& fill) {
  const std::string partial = path + ".partial";
  {
    hdf5::File file = hdf5::File::create(partial, format.role);
    file.write_attribute("format", format.name);
    file.write_attribute("format_version", format.version);
    fill(file);
    file.close();
  }
  std::error_code error;
  std::filesystem::rename(partial, path, error);
  if (error) throw Error(fmt::format("{} {}: cannot rename {} to it: {}", format.role, path, partial, error.message()));
}

}  // namespace romp::nn
