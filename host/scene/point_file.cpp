// Point files: PLY point clouds and snapshot frames as an object's particles.
#include "host/scene/point_file.h"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "host/scene/toml_reader.h"
#include "kernels/core/error.h"
#include "nn/io/snapshot_reader.h"

namespace romp::scene {
namespace {

geometry::PointCloud read_ply_points(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(fmt::format("{}: cannot open the point file", path));
  const std::string contents((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw Error(fmt::format("{}: cannot read the point file", path));
  return geometry::parse_ply_points(contents, path);
}

// X, volume0 and frame `frame`'s x (and v, when the snapshot holds it).
geometry::PointCloud read_snapshot_points(const std::string& path, std::int64_t frame) {
  const io::SnapshotReader reader(path);
  if (frame >= reader.frame_count())
    throw Error(fmt::format("{}: points_frame = {}, but the snapshot holds frames 0 .. {}", path, frame,
                            reader.frame_count() - 1));
  const io::FrameData data = reader.read_frame(frame);
  const std::size_t n = std::size_t(reader.particle_count());
  geometry::PointCloud cloud;
  for (std::size_t p = 0; p < n; ++p) {
    cloud.x.push_back(Vec3<double>(data.x[p], data.x[n + p], data.x[2 * n + p]));
    if (!data.v.empty()) cloud.v.push_back(Vec3<double>(data.v[p], data.v[n + p], data.v[2 * n + p]));
    cloud.volume.push_back(reader.header().volume0[p]);
  }
  return cloud;
}

}  // namespace

geometry::PointCloud load_points(const ObjectSpec& object, const std::string& scene_file) {
  const std::string where = fmt::format("{}: objects '{}': points = {}", scene_file, object.name, object.points_file);
  geometry::PointCloud cloud;
  try {
    cloud = std::filesystem::path(object.points_file).extension() == ".h5"
                ? read_snapshot_points(object.points_file, object.points_frame)
                : read_ply_points(object.points_file);
  } catch (const Error& error) {
    throw SceneError(fmt::format("{}: {}", where, error.what()));
  }
  if (cloud.x.empty()) throw SceneError(fmt::format("{}: the file holds no points", where));
  if (cloud.volume.empty()) {
    if (!(object.particle_volume > 0.0))
      throw SceneError(fmt::format("{}: the file gives no volume per point; set particle_volume (m^3)", where));
    cloud.volume.assign(cloud.x.size(), object.particle_volume);
  }
  // Positions are checked with every object's, against the domain (scene_setup); velocities and volumes here.
  for (std::size_t p = 0; p < cloud.x.size(); ++p) {
    if (!cloud.v.empty() &&
        !(std::isfinite(cloud.v[p][0]) && std::isfinite(cloud.v[p][1]) && std::isfinite(cloud.v[p][2])))
      throw SceneError(fmt::format("{}: point {} has a velocity that is not finite", where, p));
    if (!(cloud.volume[p] > 0.0 && std::isfinite(cloud.volume[p])))
      throw SceneError(fmt::format("{}: point {} has volume {}, not a finite value > 0", where, p, cloud.volume[p]));
  }
  return cloud;
}

}  // namespace romp::scene
