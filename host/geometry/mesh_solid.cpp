// Validation of a mesh as a solid (indices, watertightness, orientation, volume) and its inside test.
#include "host/geometry/mesh_solid.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

#include <fmt/format.h>

#include "host/geometry/primitives.h"
#include "kernels/core/error.h"

namespace romp::geometry {
namespace {

void check_indices(const TriangleMesh& mesh) {
  if (mesh.triangles.empty()) throw Error(fmt::format("mesh '{}' has no triangles", mesh.name));
  const std::int64_t count = std::int64_t(mesh.vertices.size());
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
    for (std::int32_t v : mesh.triangles[f])
      if (v < 0 || v >= count)
        throw Error(fmt::format("mesh '{}': triangle {} uses vertex {}, outside [0, {})", mesh.name, f, v, count));
  for (const Vec3<double>& v : mesh.vertices)
    for (int a = 0; a < 3; ++a)
      if (!std::isfinite(v[a]))
        throw Error(fmt::format("mesh '{}' has a non-finite vertex {}", mesh.name, describe_point(v)));
}

// Requires every edge to be used exactly once in each direction, with vertices identified by
// position (so a mesh stored with duplicated vertices, as STL-derived files are, still counts as
// closed): the condition under which the ray winding number is exact.
void check_closed(const TriangleMesh& mesh) {
  const std::vector<Vec3<double>>& x = mesh.vertices;
  std::vector<std::uint32_t> order(x.size());
  std::iota(order.begin(), order.end(), 0u);
  const auto less = [&](std::uint32_t i, std::uint32_t j) {
    return std::lexicographical_compare(x[i].v, x[i].v + 3, x[j].v, x[j].v + 3);
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<std::uint32_t> weld(x.size());
  for (std::size_t k = 0; k < order.size(); ++k)
    weld[order[k]] = (k > 0 && x[order[k]] == x[order[k - 1]]) ? weld[order[k - 1]] : order[k];

  // Directed edges u→v as u·2³² + v. A triangle with two equal vertices has no area and no edges.
  std::vector<std::uint64_t> edges;
  edges.reserve(3 * mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    const std::uint32_t w[3] = {weld[t[0]], weld[t[1]], weld[t[2]]};
    if (w[0] == w[1] || w[1] == w[2] || w[2] == w[0]) continue;
    for (int k = 0; k < 3; ++k) edges.push_back(std::uint64_t(w[k]) << 32 | w[(k + 1) % 3]);
  }
  std::sort(edges.begin(), edges.end());
  std::size_t unmatched = 0, repeated = 0;
  std::uint64_t example = 0;
  for (std::size_t k = 0; k < edges.size(); ++k) {
    const std::uint64_t reverse = edges[k] << 32 | edges[k] >> 32;
    const bool is_repeat = k > 0 && edges[k] == edges[k - 1];
    const bool is_unmatched = !std::binary_search(edges.begin(), edges.end(), reverse);
    if ((is_repeat || is_unmatched) && unmatched + repeated == 0) example = edges[k];
    repeated += is_repeat;
    unmatched += is_unmatched;
  }
  if (unmatched + repeated == 0) return;
  throw Error(fmt::format(
      "mesh '{}' is not closed and consistently oriented: {} edges lack a neighbour across them (holes) and {} "
      "are used twice in the same direction (flipped faces or non-manifold edges), the first from {} to {}; "
      "the inside test needs a watertight mesh with every face wound the same way",
      mesh.name, unmatched, repeated, describe_point(x[example >> 32]), describe_point(x[example & 0xffffffffu])));
}

}  // namespace

MeshSolid::MeshSolid(TriangleMesh mesh) {
  check_indices(mesh);
  check_closed(mesh);
  const double volume = mesh.signed_volume();
  if (!(volume > 0.0)) {
    throw Error(fmt::format(
        "mesh '{}' encloses a volume of {} by the divergence theorem; it must be > 0. A negative volume means its "
        "faces are wound clockwise seen from outside (normals facing inward): flip the winding of every face",
        mesh.name, volume));
  }
  const Bounds bounds = mesh.bounds();
  MeshInsideTest inside(mesh);
  state_ = std::make_shared<const State>(State{std::move(mesh), std::move(inside), bounds, volume});
}

std::string MeshSolid::describe() const {
  return fmt::format("mesh '{}' ({} triangles, bounds {} to {})", state_->mesh.name, state_->mesh.triangles.size(),
                     describe_point(state_->bounds.low), describe_point(state_->bounds.high));
}

}  // namespace romp::geometry
