// How this binary was built: version, commit and configuration, generated at build time.
#pragma once

namespace romp {

struct BuildInfo {
  const char* version;
  const char* commit;  // short hash, "-dirty" when built from uncommitted changes
  const char* build_type;
  const char* cxx_compiler;
  bool cuda;  // the CUDA backend is compiled in
  const char* cuda_architectures;
  const char* cuda_compiler_version;
  const char* torch_version;  // as found by CMake
  bool torch_cuda;
  const char* hdf5_version;
};

const BuildInfo& build_info();

}  // namespace romp
