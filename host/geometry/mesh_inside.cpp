// Winding number of a closed triangle mesh along a +z ray, with a bucket grid over the xy-plane.
#include "host/geometry/mesh_inside.h"

#include <algorithm>
#include <cmath>

#include "host/geometry/orientation.h"

namespace romp::geometry {
namespace {

// Cells per axis at most, so a mesh with a few huge triangles does not allocate a huge grid.
constexpr int kMaxCellsPerAxis = 2048;

// Which side of the directed edge a→b the point p + (ε, ε²) lies on, for infinitesimal ε > 0:
// +1 left, −1 right, 0 only when a and b coincide in projection. `value` receives orient2d(a, b, p).
// orient2d is affine in p with gradient (a_y − b_y, b_x − a_x), so on the edge's line the ε term
// decides, and on a horizontal edge the ε² term (Edelsbrunner & Mücke's simulation of simplicity).
int perturbed_side(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& p, double& value) {
  value = orient2d(a[0], a[1], b[0], b[1], p[0], p[1]);
  if (value != 0.0) return value > 0.0 ? 1 : -1;
  if (a[1] != b[1]) return a[1] > b[1] ? 1 : -1;
  if (a[0] != b[0]) return b[0] > a[0] ? 1 : -1;
  return 0;
}

}  // namespace

MeshInsideTest::MeshInsideTest(const TriangleMesh& mesh) : bounds_(mesh.bounds()) {
  for (const auto& t : mesh.triangles) {
    const Vec3<double>& a = mesh.vertices[t[0]];
    const Vec3<double>& b = mesh.vertices[t[1]];
    const Vec3<double>& c = mesh.vertices[t[2]];
    // A triangle parallel to the ray is never crossed by the perturbed ray.
    if (orient2d(a[0], a[1], b[0], b[1], c[0], c[1]) == 0.0) continue;
    triangles_.push_back({a, b, c, std::max({a[2], b[2], c[2]})});
  }

  // About one cell per triangle, square cells.
  const Vec3<double> size = bounds_.size();
  const double area = size[0] * size[1];
  if (area > 0.0 && !triangles_.empty()) {
    const double cell = std::sqrt(area / double(triangles_.size()));
    for (int axis = 0; axis < 2; ++axis) {
      cells_[axis] = int(std::clamp(std::ceil(size[axis] / cell), 1.0, double(kMaxCellsPerAxis)));
      inverse_cell_size_[axis] = double(cells_[axis]) / size[axis];
    }
  }

  // Bucket each triangle into the cells its projected bounding box covers (counting sort, CSR).
  // column() is monotone, so a point inside a triangle's box lands in one of these cells.
  const auto for_each_cell = [this](const Triangle& t, auto&& visit) {
    const int x0 = column(std::min({t.a[0], t.b[0], t.c[0]}), 0), x1 = column(std::max({t.a[0], t.b[0], t.c[0]}), 0);
    const int y0 = column(std::min({t.a[1], t.b[1], t.c[1]}), 1), y1 = column(std::max({t.a[1], t.b[1], t.c[1]}), 1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) visit(std::size_t(y) * std::size_t(cells_[0]) + std::size_t(x));
  };
  cell_begin_.assign(std::size_t(cells_[0]) * std::size_t(cells_[1]) + 1, 0);
  for (const Triangle& t : triangles_) for_each_cell(t, [this](std::size_t cell) { ++cell_begin_[cell + 1]; });
  for (std::size_t i = 1; i < cell_begin_.size(); ++i) cell_begin_[i] += cell_begin_[i - 1];
  cell_triangles_.resize(cell_begin_.back());
  std::vector<std::size_t> next(cell_begin_.begin(), cell_begin_.end() - 1);
  for (std::size_t i = 0; i < triangles_.size(); ++i)
    for_each_cell(triangles_[i], [&](std::size_t cell) { cell_triangles_[next[cell]++] = std::uint32_t(i); });
}

int MeshInsideTest::column(double value, int axis) const {
  const double position = std::floor((value - bounds_.low[axis]) * inverse_cell_size_[axis]);
  return int(std::clamp(position, 0.0, double(cells_[axis] - 1)));
}

std::size_t MeshInsideTest::cell_of(const Vec3<double>& p) const {
  return std::size_t(column(p[1], 1)) * std::size_t(cells_[0]) + std::size_t(column(p[0], 0));
}

int MeshInsideTest::winding_number(const Vec3<double>& p) const {
  // A closed surface encloses nothing outside its bounding box.
  if (!bounds_.contains(p)) return 0;
  const std::size_t cell = cell_of(p);
  int winding = 0;
  for (std::size_t k = cell_begin_[cell]; k < cell_begin_[cell + 1]; ++k) {
    const Triangle& t = triangles_[cell_triangles_[k]];
    if (t.z_max < p[2]) continue;  // entirely below p: the upward ray cannot cross it
    double w_c, w_a, w_b;          // orientations opposite each vertex: unnormalised barycentrics
    const int side = perturbed_side(t.a, t.b, p, w_c);
    if (side == 0 || perturbed_side(t.b, t.c, p, w_a) != side || perturbed_side(t.c, t.a, p, w_b) != side) continue;
    // Height of the crossing, written from vertex a so a triangle normal to z gives exactly a_z.
    w_a = std::abs(w_a), w_b = std::abs(w_b), w_c = std::abs(w_c);
    const double z = t.a[2] + (w_b * (t.b[2] - t.a[2]) + w_c * (t.c[2] - t.a[2])) / (w_a + w_b + w_c);
    // A counter-clockwise projection (side +1) means the triangle faces +z: the ray leaves there.
    if (z > p[2]) winding += side;
  }
  return winding;
}

}  // namespace romp::geometry
