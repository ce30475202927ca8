// HDF5 files that name their format and version in two root attributes (snapshots, run checkpoints, ROM
// models and checkpoints, neural-law files): the one check on opening, and the atomic write of a whole file.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "nn/io/hdf5_file.h"

namespace romp::io {

struct FileFormat {
  const char* role;         // in messages and HDF5 errors: "model", "checkpoint", "neural law"
  const char* name;         // root attribute format, e.g. "romp-rom-model"
  const char* description;  // "a romp ROM model", for "not a romp ROM model: ..."
  std::int64_t version;     // the newest format_version this romp reads (and writes); 1 is the oldest
};

// Opens `path` read-only. A missing file or one that is not HDF5 throws romp::Error naming it; a file of
// another format (or none) or of a format_version outside 1 .. format.version throws UnusableFileError.
hdf5::File open_versioned_file(const std::string& path, const FileFormat& format);

// Writes the root attributes format and format_version to an open file being created.
void write_format_attributes(hdf5::File& file, const FileFormat& format);

// Writes format and format_version, then `fill`, to a temporary beside `path` and renames it over `path`
// (AtomicFile): a reader never sees a half-written file, and a crash meanwhile keeps the previous one.
void write_versioned_file(const std::string& path, const FileFormat& format,
                          const std::function<void(hdf5::File&)>& fill);

}  // namespace romp::io
