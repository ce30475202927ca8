// The particles of an object read from a point file (ObjectSpec::points_file): a PLY point cloud or a
// frame of a romp snapshot.
#pragma once

#include <string>

#include "host/geometry/mesh_io.h"
#include "host/scene/scene.h"

namespace romp::scene {

// The object's points, each with its volume (the file's, or the object's particle_volume) and, where
// the file has them, its velocity. Throws SceneError naming `scene_file`, the object and the file when
// the file cannot be read, the frame does not exist, no volume is known, or a velocity or volume is not
// finite (positions are checked against the domain with every object's).
geometry::PointCloud load_points(const ObjectSpec& object, const std::string& scene_file);

}  // namespace romp::scene
