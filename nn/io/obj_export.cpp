// OBJ text, written through the atomic-file helper.
#include "nn/io/obj_export.h"

#include <fmt/format.h>

#include <filesystem>

#include "nn/io/atomic_file.h"

namespace romp::io {

void write_obj(const std::string& path, const std::vector<Vec3<double>>& vertices,
               const std::vector<std::array<std::int32_t, 3>>& triangles, const std::string& comment) {
  std::string text = fmt::format("# {}\n", comment);
  text.reserve(text.size() + 40 * vertices.size() + 24 * triangles.size());
  for (const Vec3<double>& v : vertices) text += fmt::format("v {:.7g} {:.7g} {:.7g}\n", v[0], v[1], v[2]);
  for (const std::array<std::int32_t, 3>& t : triangles)
    text += fmt::format("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  if (!folder.empty()) std::filesystem::create_directories(folder);
  write_file_atomically(path, text);
}

std::string mesh_frame_path(const std::string& snapshot_path, const std::string& name, std::int64_t frame) {
  const std::filesystem::path path(snapshot_path);
  const std::filesystem::path folder = path.parent_path() / (path.stem().string() + "_meshes");
  return (folder / fmt::format("{}_{:06d}.obj", name, frame)).string();
}

}  // namespace romp::io
