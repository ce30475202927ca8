# Generates the build-information source that `romp info` and romp-bench report.
# The commit is read at build time (every build), not at configure time, so a binary never claims
# a commit it was not built from; the file is rewritten only when its contents change.
# A CMake list inside a COMMAND argument would split into several arguments.
string(REPLACE ";" "," _romp_arch_text "${ROMP_CUDA_ARCHITECTURES_RESOLVED}")
set(ROMP_BUILD_INFO_CPP "${CMAKE_BINARY_DIR}/generated/build_info.cpp")
add_custom_target(romp_build_info_gen
  COMMAND ${CMAKE_COMMAND}
    -DSOURCE_DIR=${CMAKE_SOURCE_DIR}
    -DTEMPLATE=${CMAKE_SOURCE_DIR}/cmake/build_info.cpp.in
    -DOUTPUT=${ROMP_BUILD_INFO_CPP}
    -DROMP_VERSION=${PROJECT_VERSION}
    -DROMP_BUILD_TYPE=${CMAKE_BUILD_TYPE}
    -DROMP_WITH_CUDA=${ROMP_WITH_CUDA}
    -DROMP_CUDA_ARCHITECTURES=${_romp_arch_text}
    -DROMP_CUDA_COMPILER_VERSION=${CMAKE_CUDA_COMPILER_VERSION}
    -DROMP_CXX_COMPILER=${CMAKE_CXX_COMPILER_ID}-${CMAKE_CXX_COMPILER_VERSION}
    -DROMP_TORCH_VERSION=${Torch_VERSION}
    -DROMP_TORCH_CUDA=${ROMP_TORCH_CUDA}
    -DROMP_HDF5_VERSION=${HDF5_VERSION}
    -P ${CMAKE_SOURCE_DIR}/cmake/WriteBuildInfo.cmake
  BYPRODUCTS ${ROMP_BUILD_INFO_CPP}
  COMMENT "Recording build information"
  VERBATIM)
