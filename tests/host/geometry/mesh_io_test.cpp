// OBJ and PLY readers: the record forms they accept, and errors that name the file and the place.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>

#include "host/geometry/mesh_io.h"
#include "tests/host/geometry/test_meshes.h"

namespace romp::geometry {
namespace {

using Triangle = std::array<std::int32_t, 3>;

bool mentions(const std::string& message, const std::string& part) { return message.find(part) != std::string::npos; }

void expect_same_mesh(const TriangleMesh& read, const TriangleMesh& written) {
  ASSERT_EQ(read.vertices.size(), written.vertices.size());
  for (std::size_t v = 0; v < read.vertices.size(); ++v) EXPECT_EQ(read.vertices[v], written.vertices[v]) << v;
  EXPECT_EQ(read.triangles, written.triangles);
}

TEST(MeshReaders, ObjAcceptsPolygonsSlashFormsAndRelativeIndices) {
  const std::string text =
      "# a unit square pyramid\r\n"
      "mtllib pyramid.mtl\n"
      "o pyramid\n"
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
      "vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 -1\n"
      "v 0.5 0.5 1.0 1.0   # with a w component\r\n"
      "g base\nusemtl stone\ns off\n"
      "f 1/1/1 4/4/1 3/3/1 2/2/1\n"  // a quad: fanned into two triangles
      "f 1//1 2//1 5//1\n"
      "f -4/2 -3/3 -1/1\n"  // relative to the 5 vertices so far: 2 3 5
      "f 3 4 5\n"
      "l 1 2\n"
      "f 4 1 5\n";
  const TriangleMesh mesh = parse_obj(text, "pyramid.obj");
  ASSERT_EQ(mesh.vertices.size(), 5u);
  EXPECT_EQ(mesh.vertices[4], Vec3<double>(0.5, 0.5, 1.0));
  const std::vector<Triangle> expected = {{0, 3, 2}, {0, 2, 1}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
  EXPECT_EQ(mesh.triangles, expected);
  EXPECT_EQ(mesh.name, "pyramid.obj");
  EXPECT_NEAR(mesh.signed_volume(), 1.0 / 3.0, 1e-15);
}

TEST(MeshReaders, MeshesWrittenAsObjAndPlyReadBackExactly) {
  const test::ScratchFolder folder;
  const TriangleMesh sphere = test::icosphere_mesh(2);
  expect_same_mesh(load_mesh(folder.write("sphere.obj", test::to_obj(sphere))), sphere);
  expect_same_mesh(load_mesh(folder.write("sphere.ply", test::to_ascii_ply(sphere))), sphere);
  expect_same_mesh(load_mesh(folder.write("sphere_binary.PLY", test::to_binary_ply(sphere))), sphere);
}

TEST(MeshReaders, PlySkipsOtherPropertiesAndElements) {
  // float coordinates among other vertex properties, `vertex_index` as uint with an int count, a
  // quad, a face property after the list, and an element romp does not use.
  std::string bytes =
      "ply\nformat binary_little_endian 1.0\ncomment made by hand\nobj_info test\n"
      "element vertex 4\nproperty uchar red\nproperty float x\nproperty float y\nproperty float z\n"
      "property double nx\nelement face 1\nproperty list int uint vertex_index\nproperty short flags\n"
      "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n";
  const auto put = [&bytes](const auto& value) {
    char raw[sizeof value];
    std::memcpy(raw, &value, sizeof value);
    bytes.append(raw, sizeof value);
  };
  const float corners[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0.5f}};
  for (const auto& c : corners) {
    put(std::uint8_t(200));
    for (float x : c) put(x);
    put(1.0);
  }
  put(std::int32_t(4));
  for (std::uint32_t i : {0u, 1u, 2u, 3u}) put(i);
  put(std::int16_t(-7));
  put(std::int32_t(0));
  put(std::int32_t(1));
  const TriangleMesh mesh = parse_ply(bytes, "quad.ply");
  ASSERT_EQ(mesh.vertices.size(), 4u);
  EXPECT_EQ(mesh.vertices[3], Vec3<double>(0.0, 1.0, 0.5));
  EXPECT_EQ(mesh.triangles, (std::vector<Triangle>{{0, 1, 2}, {0, 2, 3}}));

  const std::string text =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "property uchar alpha\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0 255\n1 0 0 255\n0 1 0 255\n3 0 1 2\n";
  EXPECT_EQ(parse_ply(text, "triangle.ply").triangles, (std::vector<Triangle>{{0, 1, 2}}));
}

TEST(MeshReaders, ErrorsNameTheFileAndLine) {
  const test::ScratchFolder folder;
  const std::string bad_index = folder.write("bad_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
  EXPECT_TRUE(
      mentions(test::error_message([&] { load_mesh(bad_index); }), bad_index + ":4: vertex index 4 out of range"));
  const std::string zero_index = folder.write("zero_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
  EXPECT_TRUE(mentions(test::error_message([&] { load_mesh(zero_index); }), zero_index + ":4: bad vertex index '0'"));
  const std::string too_relative = folder.write("relative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n");
  EXPECT_TRUE(mentions(test::error_message([&] { load_mesh(too_relative); }), too_relative + ":4:"));
  const std::string bad_number = folder.write("bad_number.obj", "# header\nv 0 0 0\nv 1 0x 0\n");
  EXPECT_TRUE(
      mentions(test::error_message([&] { load_mesh(bad_number); }), bad_number + ":3: bad vertex coordinate '0x'"));
  const std::string no_faces = folder.write("no_faces.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  EXPECT_TRUE(mentions(test::error_message([&] { load_mesh(no_faces); }), no_faces + ": no faces"));
  const std::string missing = folder.file("missing.obj");
  EXPECT_TRUE(mentions(test::error_message([&] { load_mesh(missing); }), missing + ": cannot open"));
  const std::string unknown = folder.write("mesh.stl", "solid nothing\n");
  EXPECT_TRUE(mentions(test::error_message([&] { load_mesh(unknown); }), unknown + ": unknown mesh format '.stl'"));

  std::string ply = test::to_ascii_ply(test::octahedron_mesh());
  const std::string ascii_bad = folder.write("bad_number.ply", ply.replace(ply.find("\n1 0 0\n") + 1, 1, "one"));
  // The header has 10 lines; the first vertex is on line 11.
  EXPECT_TRUE(mentions(test::error_message([&] { load_mesh(ascii_bad); }), ascii_bad + ":11: bad number 'one'"));
  ply = test::to_ascii_ply(test::octahedron_mesh());
  const std::string ascii_index = folder.write("bad_index.ply", ply.replace(ply.rfind("\n3 ") + 3, 1, "6"));
  EXPECT_TRUE(mentions(test::error_message([&] { load_mesh(ascii_index); }), ascii_index + ":24: vertex index 6"));
}

TEST(MeshReaders, BinaryPlyErrorsNameTheFileAndElement) {
  const test::ScratchFolder folder;
  const std::string binary = test::to_binary_ply(test::octahedron_mesh());
  const std::string truncated = folder.write("truncated.ply", binary.substr(0, binary.size() - 5));
  EXPECT_TRUE(mentions(test::error_message([&] { load_mesh(truncated); }),
                       truncated + ": element 'face' item 7: the file is truncated"));
  std::string out_of_range = binary;
  out_of_range[out_of_range.size() - 4] = 9;  // the last face's last index
  const std::string bad_index = folder.write("bad_index.ply", out_of_range);
  EXPECT_TRUE(mentions(test::error_message([&] { load_mesh(bad_index); }),
                       bad_index + ": element 'face' item 7: vertex index 9 out of range: the file has 6 vertices"));
  std::string big_endian = binary;
  big_endian.replace(big_endian.find("binary_little_endian"), 20, "binary_big_endian");
  const std::string unsupported = folder.write("big_endian.ply", big_endian);
  EXPECT_TRUE(mentions(test::error_message([&] { load_mesh(unsupported); }),
                       unsupported + ":2: unsupported PLY format 'binary_big_endian'"));
  const std::string not_ply = folder.write("not.ply", "solid cube\nfacet normal 0 0 1\n");
  EXPECT_TRUE(mentions(test::error_message([&] { load_mesh(not_ply); }), not_ply + ":1: not a PLY file"));
  const std::string no_faces =
      folder.write("no_faces.ply",
                   "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                   "property float z\nend_header\n0 0 0\n");
  EXPECT_TRUE(mentions(test::error_message([&] { load_mesh(no_faces); }), no_faces + ": no faces"));
}

}  // namespace
}  // namespace romp::geometry
