# Decides whether the CUDA backend is built and with which architectures.
#
# ROMP_CUDA = AUTO (default) builds it whenever nvcc is found, also on machines without a GPU:
# the backend is chosen at run time. The architecture list is fixed, never `native`, so a
# configure step on a GPU-less CI machine produces the same binary as on a workstation.
set(ROMP_CUDA "AUTO" CACHE STRING "Build the CUDA backend: AUTO (when nvcc is found), ON or OFF")
set_property(CACHE ROMP_CUDA PROPERTY STRINGS AUTO ON OFF)
# sm_80 (A100) and sm_90 (H100/H200) cover the GPUs romp is measured on; 90 also embeds PTX for
# newer parts. Each extra architecture adds a full device compile, so CI keeps the list short.
set(ROMP_CUDA_ARCHITECTURES "80-real;90" CACHE STRING "CUDA architectures to compile for (never 'native')")

set(ROMP_WITH_CUDA OFF)
if(NOT ROMP_CUDA STREQUAL "OFF")
  include(CheckLanguage)
  if(NOT CMAKE_CUDA_COMPILER)
    # CMake looks for nvcc on PATH and in CUDACXX; the toolkit's default prefix is a common miss.
    find_program(ROMP_NVCC nvcc HINTS /usr/local/cuda/bin)
    if(ROMP_NVCC)
      set(CMAKE_CUDA_COMPILER "${ROMP_NVCC}" CACHE FILEPATH "CUDA compiler")
    endif()
  endif()
  check_language(CUDA)
  if(CMAKE_CUDA_COMPILER)
    set(ROMP_WITH_CUDA ON)
  elseif(ROMP_CUDA STREQUAL "ON")
    message(FATAL_ERROR "ROMP_CUDA=ON but no CUDA compiler (nvcc) was found; set CUDACXX or use -DROMP_CUDA=OFF")
  endif()
endif()

if(ROMP_WITH_CUDA)
  if(ROMP_CUDA_ARCHITECTURES MATCHES "native|all")
    message(FATAL_ERROR "ROMP_CUDA_ARCHITECTURES='${ROMP_CUDA_ARCHITECTURES}': give a fixed list such as '80-real;90'")
  endif()
  set(CMAKE_CUDA_ARCHITECTURES "${ROMP_CUDA_ARCHITECTURES}")
  set(CMAKE_CUDA_STANDARD 17)
  set(CMAKE_CUDA_STANDARD_REQUIRED ON)
  enable_language(CUDA)
  find_package(CUDAToolkit REQUIRED)
  set(ROMP_CUDA_ARCHITECTURES_RESOLVED "${ROMP_CUDA_ARCHITECTURES}")
  # Every device compile keeps ptxas's resource report (registers, stack frame, spills per kernel) beside
  # its object, so that CI, which has nvcc and no GPU, checks the hot kernels against their budgets
  # (tests/kernels/kernel_resources.toml) at no extra compile. A launcher of the user's own comes first.
  if(NOT CMAKE_CUDA_COMPILER_LAUNCHER)
    set(CMAKE_CUDA_COMPILER_LAUNCHER "${CMAKE_CURRENT_LIST_DIR}/keep_resource_report.sh")
  else()
    set(CMAKE_CUDA_COMPILER_LAUNCHER "${CMAKE_CURRENT_LIST_DIR}/keep_resource_report.sh;${CMAKE_CUDA_COMPILER_LAUNCHER}")
  endif()
else()
  set(ROMP_CUDA_ARCHITECTURES_RESOLVED "none")
endif()

# romp_single_source(<target> <files...>): files that hold ROMP_HD functors launched through
# romp::for_each. They are written as .cu; without CUDA they are compiled as plain C++ so the
# OpenMP path of the same source is what runs.
function(romp_single_source target)
  target_sources(${target} PRIVATE ${ARGN})
  if(NOT ROMP_WITH_CUDA)
    set_source_files_properties(${ARGN} TARGET_DIRECTORY ${target} PROPERTIES LANGUAGE CXX)
  endif()
endfunction()

# romp_use_backend(<target>): compile flags and libraries every target using kernels/core needs.
function(romp_use_backend target)
  target_link_libraries(${target} PUBLIC OpenMP::OpenMP_CXX)
  target_compile_options(${target} PRIVATE
    $<$<COMPILE_LANGUAGE:CUDA>:--extended-lambda --expt-relaxed-constexpr -Xcompiler=-fopenmp --resource-usage>)
  if(ROMP_WITH_CUDA)
    target_compile_definitions(${target} PUBLIC ROMP_WITH_CUDA=1)
    target_link_libraries(${target} PUBLIC CUDA::cudart)
  endif()
endfunction()
