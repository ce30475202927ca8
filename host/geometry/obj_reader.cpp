// Wavefront OBJ reader: vertices and faces, fan-triangulated; every other record is ignored.
#include <algorithm>
#include <cstdint>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "host/geometry/mesh_io.h"
#include "host/geometry/parse_number.h"
#include "kernels/core/error.h"

namespace romp::geometry {
namespace {

// The whitespace-separated tokens of one line, up to a '#' comment.
std::vector<std::string_view> tokens_of(std::string_view line) {
  line = line.substr(0, line.find('#'));
  std::vector<std::string_view> tokens;
  std::size_t at = 0;
  while (true) {
    at = line.find_first_not_of(" \t\r\f\v", at);
    if (at == std::string_view::npos) break;
    const std::size_t end = std::min(line.find_first_of(" \t\r\f\v", at), line.size());
    tokens.push_back(line.substr(at, end - at));
    at = end;
  }
  return tokens;
}

}  // namespace

TriangleMesh parse_obj(const std::string& text, const std::string& name) {
  TriangleMesh mesh;
  mesh.name = name;
  std::vector<std::int32_t> polygon;
  std::size_t line_number = 0;
  for (std::size_t start = 0; start < text.size();) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    const std::vector<std::string_view> tokens = tokens_of(std::string_view(text).substr(start, end - start));
    start = end + 1;
    ++line_number;
    if (tokens.empty()) continue;
    const auto fail = [&](const std::string& why) { throw Error(fmt::format("{}:{}: {}", name, line_number, why)); };

    if (tokens[0] == "v") {
      if (tokens.size() < 4) fail("a vertex needs three coordinates: v x y z");
      Vec3<double> x;
      for (int a = 0; a < 3; ++a)
        if (!parse_double(tokens[1 + a], x[a])) fail(fmt::format("bad vertex coordinate '{}'", tokens[1 + a]));
      mesh.vertices.push_back(x);
    } else if (tokens[0] == "f") {
      if (tokens.size() < 4) fail("a face needs at least three vertices");
      polygon.clear();
      const std::int64_t defined = std::int64_t(mesh.vertices.size());
      for (std::size_t k = 1; k < tokens.size(); ++k) {
        // i, i/t, i/t/n or i//n: the vertex index is the part before the first '/'.
        const std::string_view reference = tokens[k].substr(0, tokens[k].find('/'));
        std::int64_t index = 0;
        if (!parse_integer(reference, index) || index == 0) fail(fmt::format("bad vertex index '{}'", tokens[k]));
        // Positive indices count from 1; negative ones back from the last vertex defined so far.
        const std::int64_t resolved = index > 0 ? index - 1 : defined + index;
        if (resolved < 0 || resolved >= defined)
          fail(fmt::format("vertex index {} out of range: {} vertices are defined before this line", index, defined));
        polygon.push_back(std::int32_t(resolved));
      }
      for (std::size_t k = 1; k + 1 < polygon.size(); ++k)
        mesh.triangles.push_back({polygon[0], polygon[k], polygon[k + 1]});
    }
  }
  if (mesh.triangles.empty()) throw Error(fmt::format("{}: no faces (no 'f' records)", name));
  return mesh;
}

}  // namespace romp::geometry
