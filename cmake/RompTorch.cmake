# Finds LibTorch without letting it disturb the CUDA configuration of the rest of the build.
#
# Debian's libtorch-dev (CPU) is found through the default prefixes. On GPU machines the LibTorch
# inside the PyTorch install is used: when Torch_DIR is not given, ask the Python interpreter.
# Torch's package config (Caffe2's public/cuda.cmake) rewrites CMAKE_CUDA_ARCHITECTURES and
# CMAKE_CUDA_FLAGS from TORCH_CUDA_ARCH_LIST and attaches host-only link options to its targets.
# We restore the CUDA variables afterwards, and only C++ targets (nn/, host/) ever link Torch.
if(NOT Torch_DIR)
  find_package(Python3 COMPONENTS Interpreter QUIET)
  if(Python3_Interpreter_FOUND)
    execute_process(
      COMMAND "${Python3_EXECUTABLE}" -c "import torch.utils; print(torch.utils.cmake_prefix_path)"
      OUTPUT_VARIABLE _romp_torch_prefix OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET
      RESULT_VARIABLE _romp_torch_rc)
    if(_romp_torch_rc EQUAL 0 AND EXISTS "${_romp_torch_prefix}")
      list(APPEND CMAKE_PREFIX_PATH "${_romp_torch_prefix}")
    endif()
  endif()
endif()

# TorchConfig.cmake finds its Caffe2 package and its libraries with PATHS hints, which CMake searches
# after the system's folders: where Debian's libtorch-dev is installed too, a Torch_DIR of PyTorch's
# wheel would otherwise mix the wheel's headers with Debian's libraries. Its install prefix (the folder
# that holds share/cmake/Torch) goes first.
if(Torch_DIR)
  get_filename_component(_romp_torch_install_prefix "${Torch_DIR}/../../.." ABSOLUTE)
  list(PREPEND CMAKE_PREFIX_PATH "${_romp_torch_install_prefix}")
endif()

set(_romp_saved_cuda_arch "${CMAKE_CUDA_ARCHITECTURES}")
set(_romp_saved_cuda_flags "${CMAKE_CUDA_FLAGS}")
find_package(Torch REQUIRED)
set(CMAKE_CUDA_ARCHITECTURES "${_romp_saved_cuda_arch}")
set(CMAKE_CUDA_FLAGS "${_romp_saved_cuda_flags}")

# LibTorch built with CUDA ships torch_cuda (or c10_cuda) next to torch_cpu.
set(ROMP_TORCH_CUDA OFF)
foreach(_lib IN LISTS TORCH_LIBRARIES)
  if(_lib MATCHES "torch_cuda|c10_cuda")
    set(ROMP_TORCH_CUDA ON)
  endif()
endforeach()
if(TARGET torch_cuda OR TARGET c10_cuda)
  set(ROMP_TORCH_CUDA ON)
endif()

# One interface target for the C++ code that uses Torch: its flags, its libraries, and the
# information `romp info` reports.
add_library(romp_torch INTERFACE)
# PyTorch's wheel links parts of its own libstdc++ (std::filesystem, the chrono time zones) into
# libtorch.so and libtorch_cpu.so and exports them. The linker binds each undefined symbol to the
# first shared library on the link line that defines it, and the loader searches libraries in that
# same order, so romp's calls of std::filesystem went to LibTorch's copies, which crash (remove_all
# jumps to address 0). libstdc++ named ahead of LibTorch keeps the system's standard library the one
# romp calls (tests/nn/runtime_libraries_test.cpp).
target_link_libraries(romp_torch INTERFACE stdc++ ${TORCH_LIBRARIES})
target_compile_definitions(romp_torch INTERFACE ROMP_TORCH_CUDA=$<BOOL:${ROMP_TORCH_CUDA}>)
# The libstdc++ ABI LibTorch was built with must hold for every romp object, not only the ones
# that include Torch headers: std::string crosses between all the libraries.
if(TORCH_CXX_FLAGS MATCHES "-D_GLIBCXX_USE_CXX11_ABI=([01])")
  add_compile_definitions(_GLIBCXX_USE_CXX11_ABI=${CMAKE_MATCH_1})
endif()

# Parsing <torch/torch.h> costs every translation unit that includes it about 17 s on the project's
# 2-core CPU machine, and loading it precompiled about 7 s (one-line file, -O3). romp_nn precompiles it
# once (nn/CMakeLists.txt) and each target whose C++ files include LibTorch reuses that header:
#   romp_reuse_torch_pch(<target> [<source>...])
# With sources given, only those load it and the target's other files skip it (for them the 7 s would
# be pure cost). GCC accepts a precompiled header only where it was built with the same code model, so
# the build leaves position independence at the compiler's default for libraries and executables alike
# (see CMakeLists.txt).
function(romp_reuse_torch_pch target)
  target_precompile_headers(${target} REUSE_FROM romp_nn)
  if(ARGN)
    get_target_property(sources ${target} SOURCES)
    # A misspelt name would silently leave its file on the slow path.
    foreach(source IN LISTS ARGN)
      if(NOT source IN_LIST sources)
        message(FATAL_ERROR "romp_reuse_torch_pch(${target}): '${source}' is not one of its sources")
      endif()
    endforeach()
    list(REMOVE_ITEM sources ${ARGN})
    set_source_files_properties(${sources} TARGET_DIRECTORY ${target} PROPERTIES SKIP_PRECOMPILE_HEADERS ON)
  endif()
endfunction()
