// MeshSolid: the solid that a closed, outward-facing triangle mesh encloses, as a shape for sampling.
#pragma once

#include <memory>
#include <string>

#include "host/geometry/bounds.h"
#include "host/geometry/mesh_inside.h"
#include "host/geometry/triangle_mesh.h"

namespace romp::geometry {

class MeshSolid {
 public:
  // Checks the mesh and builds its inside test. Throws romp::Error naming the mesh when an index is
  // out of range, when it is not closed and consistently oriented (every edge, vertices identified
  // by position, used once in each direction), or when its volume is not positive (inward normals).
  explicit MeshSolid(TriangleMesh mesh);

  bool contains(const Vec3<double>& p) const { return state_->inside.contains(p); }
  Bounds bounds() const { return state_->bounds; }
  // The divergence-theorem volume.
  double analytic_volume() const { return state_->volume; }
  std::string describe() const;
  const TriangleMesh& mesh() const { return state_->mesh; }

 private:
  // Shared and immutable, so copying a Shape does not copy the mesh or its grid.
  struct State {
    TriangleMesh mesh;
    MeshInsideTest inside;
    Bounds bounds;
    double volume;
  };
  std::shared_ptr<const State> state_;
};

}  // namespace romp::geometry
