// HDF5 files that name their format and version in two root attributes (ROM models and checkpoints,
// neural-law files): the check on opening, and the write to "<path>.partial" renamed to `path` once complete.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "nn/hdf5_file.h"

namespace romp::nn {

struct FileFormat {
  const char* role;         // in messages and HDF5 errors: "model", "checkpoint", "neural law"
  const char* name;         // root attribute format, e.g. "romp-rom-model"
  const char* description;  // "a romp ROM model", for "not a romp ROM model: ..."
  std::int64_t version;     // the newest format_version this romp reads (and writes); 1 is the oldest
};

// Opens `path` read-only; throws romp::Error naming the file when it is missing, not HDF5, not of `format` or of
// a format_version outside 1 .. format.version.
hdf5::File open_versioned_file(const std::string& path, const FileFormat& format);

// Writes format and format_version, then `fill`, to "<path>.partial", closes it and renames it to `path`: a
// reader never sees a half-written file, and a crash meanwhile keeps the previous one.
void write_versioned_file(const std::string& path, const FileFormat& format,
                          const std::function<void(hdf5::File&)>& fill);

}  // namespace romp::nn
