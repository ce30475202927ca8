# The libraries every romp target may use, found in one place so that the build and the test of its
# include order (tests/build/fmt_clash) configure them the same way.
find_package(OpenMP REQUIRED COMPONENTS CXX)
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(HDF5 REQUIRED COMPONENTS C)
find_package(fmt REQUIRED)
find_package(spdlog REQUIRED)
find_package(CLI11 REQUIRED)
find_package(tomlplusplus 3 REQUIRED)
include(RompHeadersAheadOfTorch)
romp_headers_ahead_of_torch("${CMAKE_BINARY_DIR}/ahead-of-torch" fmt::fmt:fmt/format.h spdlog::spdlog:spdlog/spdlog.h)
include(RompTorch)
