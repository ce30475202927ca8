// PLY exports: read back with a small binary PLY reader, per frame beside the snapshot.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <random>
#include <sstream>

#include "kernels/core/error.h"
#include "nn/io/ply_export.h"
#include "nn/io/snapshot_writer.h"
#include "tests/nn/io/io_test_support.h"

namespace romp::io::testing {
namespace {

using Ply = IoTest;

// A vertex-only binary little-endian PLY file with 4-byte float and int properties.
struct PlyFile {
  std::vector<std::string> header_lines;
  std::vector<std::string> properties;  // "float x", ...
  std::int64_t count = 0;
  std::string body;

  // Property `name` of vertex `index`, as T (float or std::int32_t).
  template <class T>
  T value(std::int64_t index, const std::string& name) const {
    std::size_t offset = 0;
    for (const std::string& property : properties) {
      if (property.substr(property.find(' ') + 1) == name) break;
      offset += 4;
    }
    T result;
    std::memcpy(&result, body.data() + std::size_t(index) * properties.size() * 4 + offset, 4);
    return result;
  }
};

PlyFile read_ply(const std::string& path) {
  const std::string bytes = read_file(path);
  const std::size_t end = bytes.find("end_header\n");
  EXPECT_NE(end, std::string::npos);
  PlyFile ply;
  std::istringstream header(bytes.substr(0, end));
  for (std::string line; std::getline(header, line);) {
    ply.header_lines.push_back(line);
    if (line.rfind("element vertex ", 0) == 0) ply.count = std::stoll(line.substr(15));
    if (line.rfind("property ", 0) == 0) ply.properties.push_back(line.substr(9));
  }
  ply.body = bytes.substr(end + 11);
  EXPECT_EQ(ply.body.size(), std::size_t(ply.count) * ply.properties.size() * 4);
  return ply;
}

TEST_F(Ply, PositionsVelocitiesAndMaterialRoundTrip) {
  std::mt19937 random(41);
  const std::int64_t n = 25;
  const FrameData frame = random_frame(n, 0.0, 0, random);
  const std::vector<std::int32_t> material = random_header(n, random).material;
  const std::string path = file("points.ply");
  write_ply(path,
            {Span<const float>(frame.x.data(), 3 * n), Span<const float>(frame.v.data(), 3 * n),
             Span<const std::int32_t>(material.data(), n)},
            "romp test");

  const PlyFile ply = read_ply(path);
  EXPECT_EQ(ply.header_lines[0], "ply");
  EXPECT_EQ(ply.header_lines[1], "format binary_little_endian 1.0");
  EXPECT_EQ(ply.header_lines[2], "comment romp test");
  EXPECT_EQ(ply.properties, (std::vector<std::string>{"float x", "float y", "float z", "float vx", "float vy",
                                                      "float vz", "int material"}));
  ASSERT_EQ(ply.count, n);
  const char* axes[] = {"x", "y", "z"};
  const char* velocity_axes[] = {"vx", "vy", "vz"};
  for (std::int64_t p = 0; p < n; ++p) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(ply.value<float>(p, axes[c]), frame.x[std::size_t(c * n + p)]);
      EXPECT_EQ(ply.value<float>(p, velocity_axes[c]), frame.v[std::size_t(c * n + p)]);
    }
    EXPECT_EQ(ply.value<std::int32_t>(p, "material"), material[std::size_t(p)]);
  }
}

TEST_F(Ply, PositionsOnly) {
  const std::vector<float> x{1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f};  // two points: (1,3,5), (2,4,6)
  write_ply(file("x.ply"), {Span<const float>(x.data(), 6), {}, {}}, "");
  const PlyFile ply = read_ply(file("x.ply"));
  EXPECT_EQ(ply.properties, (std::vector<std::string>{"float x", "float y", "float z"}));
  EXPECT_EQ(ply.value<float>(1, "y"), 4.0f);
  EXPECT_EQ(ply.value<float>(0, "z"), 5.0f);
  EXPECT_THROW(write_ply(file("bad.ply"), {Span<const float>(x.data(), 6), Span<const float>(x.data(), 3), {}}, ""),
               Error);
  EXPECT_EQ(folder_contents(), (std::vector<std::string>{"x.ply"}));
}

TEST_F(Ply, SnapshotWriterWritesOneFilePerFrame) {
  std::mt19937 random(42);
  const std::string path = file("run.h5");
  // A stale frame of an earlier, longer run is removed when a new run starts.
  std::filesystem::create_directories(folder_.path() / "run_ply");
  std::ofstream(folder_.path() / "run_ply" / "frame_000007.ply") << "stale";
  // No velocities selected: the PLY files carry none either.
  SnapshotWriter writer(path, random_header(12, random), kFieldX | kFieldF, true);
  std::vector<FrameData> frames;
  for (int k = 0; k < 3; ++k) {
    frames.push_back(random_frame(12, 0.25 * k, k, random));
    writer.append_frame(frames.back());
  }
  writer.finish();

  EXPECT_EQ(ply_frame_path(path, 2), (folder_.path() / "run_ply" / "frame_000002.ply").string());
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(folder_.path() / "run_ply")) {
    names.push_back(entry.path().filename());
  }
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"frame_000000.ply", "frame_000001.ply", "frame_000002.ply"}));
  const PlyFile ply = read_ply(ply_frame_path(path, 1));
  EXPECT_EQ(ply.properties, (std::vector<std::string>{"float x", "float y", "float z", "int material"}));
  EXPECT_EQ(ply.value<float>(5, "y"), frames[1].x[12 + 5]);
  EXPECT_EQ(ply.header_lines[2], "comment romp frame 1 time 0.25 step 1");
}

TEST_F(Ply, ResumeRemovesTheFilesOfDroppedFrames) {
  std::mt19937 random(43);
  const std::string path = file("run.h5");
  const SnapshotHeader header = random_header(6, random);
  {
    SnapshotWriter writer(path, header, kAllFields, true);
    for (int k = 0; k < 4; ++k) writer.append_frame(random_frame(6, 0.1 * k, k, random));
  }  // interrupted
  SnapshotWriter resumed = SnapshotWriter::resume(path, header, kAllFields, 2, true);
  EXPECT_TRUE(std::filesystem::exists(ply_frame_path(path, 1)));
  EXPECT_FALSE(std::filesystem::exists(ply_frame_path(path, 2)));
  EXPECT_FALSE(std::filesystem::exists(ply_frame_path(path, 3)));
  resumed.append_frame(random_frame(6, 0.2, 2, random));
  EXPECT_TRUE(std::filesystem::exists(ply_frame_path(path, 2)));
}

}  // namespace
}  // namespace romp::io::testing
