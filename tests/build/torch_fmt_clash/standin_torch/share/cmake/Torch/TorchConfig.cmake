# Stand-in for the TorchConfig.cmake of PyTorch's wheel, as far as romp's build sees it: a library
# target whose include folder (torch/include, given as a system folder) also holds fmt/ headers.
get_filename_component(_standin_root "${CMAKE_CURRENT_LIST_DIR}/../../.." ABSOLUTE)
if(NOT TARGET torch)
  add_library(torch INTERFACE IMPORTED)
  set_target_properties(torch PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_standin_root}/include")
endif()
set(TORCH_LIBRARIES torch)
set(TORCH_CXX_FLAGS "-D_GLIBCXX_USE_CXX11_ABI=1")
set(Torch_VERSION 0.0.0)
set(Torch_FOUND TRUE)
