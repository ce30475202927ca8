// load_mesh: reads a mesh file and hands it to the reader its extension names.
#include "host/geometry/mesh_io.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <iterator>

#include <fmt/format.h>

#include "kernels/core/error.h"

namespace romp::geometry {

TriangleMesh load_mesh(const std::string& path) {
  const std::size_t slash = path.find_last_of("/\\");
  const std::size_t dot = path.find_last_of('.');
  std::string extension =
      dot == std::string::npos || (slash != std::string::npos && dot < slash) ? "" : path.substr(dot);
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if (extension != ".obj" && extension != ".ply")
    throw Error(fmt::format("{}: unknown mesh format '{}' (romp reads .obj and .ply)", path, extension));

  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(fmt::format("{}: cannot open the mesh file", path));
  const std::string contents((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw Error(fmt::format("{}: cannot read the mesh file", path));
  return extension == ".obj" ? parse_obj(contents, path) : parse_ply(contents, path);
}

}  // namespace romp::geometry
