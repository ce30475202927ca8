// The error of an input file romp cannot use, whatever its format.
#pragma once

#include "kernels/core/error.h"

namespace romp::io {

// A file whose content cannot be used: missing, not of its format (not HDF5, not JSON, another format or
// version), an object missing or of the wrong kind, type or shape, damaged (a checksum fails on reading),
// or values no run could have written. The input's fault, not the machine's: the romp command exits 3 for
// it (README "Exit codes"). Failures to create or write a file stay romp::Error.
class UnusableFileError : public Error {
 public:
  using Error::Error;
};

}  // namespace romp::io
