# Keeps the fmt and spdlog headers romp is built against ahead of the copies other packages ship.
#
# PyTorch's wheel puts fmt 11 headers in torch/include, which every target linking Torch receives
# as a system include folder (-isystem). Debian's spdlog 1.10 is built for fmt 9; when fmt 11's
# headers are found first it stops compiling ('basic_runtime' is not a member of 'fmt'), and even
# where it compiled, the headers would disagree with the fmt library that is linked. GCC and nvcc
# search -I folders before any -isystem folder, so each package gets a folder of its own, holding
# only a link to its header tree, as an ordinary include folder of every target. A link to the one
# tree, not the package's whole prefix (often /usr/include): that must stay a system folder.
#
#   romp_headers_ahead_of_torch(<folder> <target>:<header>...)
# e.g. romp_headers_ahead_of_torch(${CMAKE_BINARY_DIR}/ahead-of-torch fmt::fmt:fmt/format.h) links
# <folder>/fmt to the fmt/ tree of fmt::fmt's include folder and adds <folder> to every target
# defined after the call in this directory and below.
function(romp_headers_ahead_of_torch folder)
  file(MAKE_DIRECTORY "${folder}")
  foreach(entry IN LISTS ARGN)
    string(REGEX MATCH "^(.+):([^:]+)$" matched "${entry}")
    if(NOT matched)
      message(FATAL_ERROR "romp_headers_ahead_of_torch: '${entry}' is not <target>:<header>")
    endif()
    set(target "${CMAKE_MATCH_1}")
    set(header "${CMAKE_MATCH_2}")
    string(REGEX REPLACE "/.*" "" tree "${header}")
    get_target_property(candidates ${target} INTERFACE_INCLUDE_DIRECTORIES)
    set(found "")
    foreach(dir IN LISTS candidates)
      if(NOT found AND EXISTS "${dir}/${header}")
        set(found "${dir}/${tree}")
      endif()
    endforeach()
    if(NOT found)
      message(FATAL_ERROR "romp_headers_ahead_of_torch: no ${header} in the include folders of ${target} (${candidates})")
    endif()
    file(REMOVE "${folder}/${tree}")
    file(CREATE_LINK "${found}" "${folder}/${tree}" SYMBOLIC)
  endforeach()
  include_directories(BEFORE "${folder}")
endfunction()
