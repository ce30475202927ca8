// Snapshot files: bitwise round trips, field selection, the .partial → final rename, resume, and
// readers that reject what is not a (complete) romp snapshot with messages naming file and object.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <random>

#include "kernels/core/error.h"
#include "nn/io/hdf5_file.h"
#include "nn/io/snapshot_reader.h"
#include "nn/io/snapshot_writer.h"
#include "tests/nn/io/io_test_support.h"

namespace romp::io::testing {
namespace {

using Snapshot = IoTest;

constexpr std::int64_t kParticles = 1000;

// Writes `frames` random frames with every field and returns them.
std::vector<FrameData> write_snapshot(const std::string& path, const SnapshotHeader& header, int frames,
                                      std::mt19937& random, bool finish = true) {
  SnapshotWriter writer(path, header, kAllFields);
  std::vector<FrameData> written;
  for (int k = 0; k < frames; ++k) {
    written.push_back(random_frame(header.particle_count(), 0.1 * k, 17 * k, random));
    writer.append_frame(written.back());
  }
  if (finish) writer.finish();
  return written;
}

TEST_F(Snapshot, EveryFieldRoundTripsBitwise) {
  std::mt19937 random(1);
  const SnapshotHeader header = random_header(kParticles, random);
  const std::string path = file("run.h5");
  SnapshotWriter writer(path, header, kAllFields);
  std::vector<FrameData> frames;
  for (int k = 0; k < 3; ++k) {
    frames.push_back(random_frame(kParticles, 0.1 * k, 1000000000000ll + k, random));
    writer.append_frame(frames.back());
  }
  // Values a conversion would disturb: signed zero, a subnormal, infinity and a NaN payload.
  FrameData special = random_frame(kParticles, 1.0 / 3.0, 99, random);
  special.x[0] = -0.0f;
  special.F[5] = std::numeric_limits<float>::denorm_min();
  special.C[17] = -std::numeric_limits<float>::infinity();
  std::uint32_t nan_bits = 0x7fc01234u;
  std::memcpy(&special.v[3], &nan_bits, 4);
  writer.append_frame(special);
  frames.push_back(special);
  writer.finish();

  const SnapshotReader reader(path);
  EXPECT_EQ(reader.particle_count(), kParticles);
  EXPECT_EQ(reader.fields(), kAllFields);
  ASSERT_EQ(reader.frame_count(), 4);
  EXPECT_EQ(reader.header().scene, header.scene);
  EXPECT_EQ(reader.header().parameter_names, header.parameter_names);
  EXPECT_EQ(reader.header().parameter_values, header.parameter_values);
  EXPECT_EQ(reader.header().romp_version, header.romp_version);
  EXPECT_EQ(reader.header().commit, header.commit);
  EXPECT_TRUE(bitwise_equal(reader.header().X, header.X));
  EXPECT_TRUE(bitwise_equal(reader.header().mass, header.mass));
  EXPECT_TRUE(bitwise_equal(reader.header().volume0, header.volume0));
  EXPECT_EQ(reader.header().material, header.material);
  EXPECT_EQ(reader.header().group, header.group);
  for (std::int64_t k = 0; k < 4; ++k) {
    const FrameData frame = reader.read_frame(k);
    const FrameData& expected = frames[std::size_t(k)];
    EXPECT_EQ(frame.time, expected.time);
    EXPECT_EQ(frame.step, expected.step);
    EXPECT_EQ(reader.frame_time(k), expected.time);
    EXPECT_EQ(reader.frame_step(k), expected.step);
    for (const FieldInfo& info : kFieldInfos)
      EXPECT_TRUE(bitwise_equal(frame.field(info.bit), expected.field(info.bit))) << info.name << ", frame " << k;
    ASSERT_TRUE(frame.totals.has_value());
    EXPECT_EQ(frame.totals->kinetic_energy, expected.totals->kinetic_energy);
    EXPECT_EQ(frame.totals->elastic_energy, expected.totals->elastic_energy);
    EXPECT_EQ(frame.totals->gravitational_energy, expected.totals->gravitational_energy);
    EXPECT_EQ(frame.totals->linear_momentum, expected.totals->linear_momentum);
    EXPECT_EQ(frame.totals->angular_momentum, expected.totals->angular_momentum);
  }
}

TEST_F(Snapshot, DatasetsAreParticleMajorForOtherReaders) {
  std::mt19937 random(2);
  const SnapshotHeader header = random_header(4, random);
  const std::string path = file("layout.h5");
  const std::vector<FrameData> frames = write_snapshot(path, header, 1, random);
  const io::hdf5::File file = io::hdf5::File::open(path, io::hdf5::Mode::ReadOnly, "snapshot");
  const std::vector<float> F = file.read_dataset<float>("/frames/000000/F", {4, 3, 3});
  // F[p][i][j] (h5py's F[p, i, j]) is engine plane 3 i + j at particle p.
  EXPECT_EQ(F[2 * 9 + 1 * 3 + 2], frames[0].F[(3 * 1 + 2) * 4 + 2]);
  const std::vector<float> X = file.read_dataset<float>("/particles/X", {4, 3});
  EXPECT_EQ(X[3 * 3 + 1], header.X[1 * 4 + 3]);
  EXPECT_EQ(file.read_dataset<std::int32_t>("/particles/id", {4}), (std::vector<std::int32_t>{0, 1, 2, 3}));
  EXPECT_EQ(file.read_string_attribute("format"), "romp-snapshot");
  EXPECT_EQ(file.read_int64_attribute("format_version"), 1);
  EXPECT_EQ(file.read_strings_attribute("fields"),
            (std::vector<std::string>{"x", "v", "F", "C", "stress", "J", "von_mises", "energy_density", "Jp",
                                      "plastic_strain"}));
  EXPECT_EQ(file.read_dataset<float>("/frames/000000/J", {4}), frames[0].J);
}

TEST_F(Snapshot, OnlySelectedFieldsAreWritten) {
  std::mt19937 random(3);
  const SnapshotHeader header = random_header(10, random);
  const std::string path = file("selected.h5");
  const FieldMask fields = parse_fields({"F"});
  EXPECT_EQ(fields, kFieldX | kFieldF);
  SnapshotWriter writer(path, header, fields);
  FrameData frame = random_frame(10, 0.0, 0, random);
  frame.v.clear();  // unselected fields need not be filled
  frame.C.clear();
  writer.append_frame(frame);
  writer.finish();

  const io::hdf5::File file = io::hdf5::File::open(path, io::hdf5::Mode::ReadOnly, "snapshot");
  EXPECT_TRUE(file.is_dataset("/frames/000000/x"));
  EXPECT_TRUE(file.is_dataset("/frames/000000/F"));
  EXPECT_FALSE(file.exists("/frames/000000/v"));
  EXPECT_FALSE(file.exists("/frames/000000/C"));
  const SnapshotReader reader(path);
  EXPECT_EQ(reader.fields(), kFieldX | kFieldF);
  const FrameData back = reader.read_frame(0);
  EXPECT_TRUE(bitwise_equal(back.F, frame.F));
  EXPECT_TRUE(back.v.empty());
  EXPECT_TRUE(back.C.empty());
  EXPECT_THROW(parse_fields({"sigma"}), Error);
}

TEST_F(Snapshot, AFrameWithoutASelectedFieldIsRejectedBeforeWriting) {
  std::mt19937 random(4);
  SnapshotWriter writer(file("short.h5"), random_header(10, random), kAllFields);
  FrameData frame = random_frame(10, 0.0, 0, random);
  frame.C.pop_back();
  EXPECT_THROW(writer.append_frame(frame), Error);
  EXPECT_EQ(writer.frame_count(), 0);
  writer.append_frame(random_frame(10, 0.0, 0, random));  // frame 0 is still free
  EXPECT_EQ(writer.frame_count(), 1);
}

TEST_F(Snapshot, TheFinalFileAppearsOnlyWhenFinished) {
  std::mt19937 random(5);
  const std::string path = file("out/run.h5");  // the folder is created
  SnapshotWriter writer(path, random_header(10, random), kAllFields);
  writer.append_frame(random_frame(10, 0.0, 0, random));
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_TRUE(std::filesystem::exists(partial_path(path)));
  writer.finish();
  EXPECT_TRUE(writer.finished());
  EXPECT_THROW(writer.append_frame(random_frame(10, 0.1, 1, random)), Error);
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(folder_.path() / "out")) {
    names.push_back(entry.path().filename());
  }
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"run.h5", "run.xdmf"}));  // no .partial, no temporaries
}

TEST_F(Snapshot, APartialFileIsReadableBetweenFrames) {
  std::mt19937 random(6);
  const std::string path = file("running.h5");
  SnapshotWriter writer(path, random_header(50, random), kAllFields);
  const FrameData first = random_frame(50, 0.0, 0, random);
  writer.append_frame(first);
  writer.append_frame(random_frame(50, 0.1, 5, random));
  // What a crash now would leave on disk: a copy of the file while the writer still holds it open.
  std::filesystem::copy_file(partial_path(path), file("crashed.h5"));
  const SnapshotReader reader(file("crashed.h5"));
  EXPECT_EQ(reader.frame_count(), 2);
  EXPECT_TRUE(bitwise_equal(reader.read_frame(0).x, first.x));
  // The running file itself opens too (a viewer during the run).
  EXPECT_EQ(SnapshotReader(partial_path(path)).frame_count(), 2);
}

TEST_F(Snapshot, ResumeKeepsEarlierFramesAndDropsLaterOnes) {
  std::mt19937 random(7);
  const SnapshotHeader header = random_header(20, random);
  const std::string path = file("resume.h5");
  const std::vector<FrameData> frames = write_snapshot(path, header, 4, random, false);  // interrupted

  SnapshotWriter resumed = SnapshotWriter::resume(path, header, kAllFields, 2);
  EXPECT_EQ(resumed.frame_count(), 2);
  EXPECT_EQ(SnapshotReader(partial_path(path)).frame_count(), 2);
  const FrameData replacement = random_frame(20, 0.2, 34, random);
  resumed.append_frame(replacement);
  resumed.finish();

  const SnapshotReader reader(path);
  ASSERT_EQ(reader.frame_count(), 3);
  EXPECT_TRUE(bitwise_equal(reader.read_frame(0).x, frames[0].x));
  EXPECT_TRUE(bitwise_equal(reader.read_frame(1).C, frames[1].C));
  EXPECT_TRUE(bitwise_equal(reader.read_frame(2).v, replacement.v));
  EXPECT_FALSE(io::hdf5::File::open(path, io::hdf5::Mode::ReadOnly, "snapshot").exists("/frames/000003"));
}

TEST_F(Snapshot, ResumeRejectsAFileOfAnotherRun) {
  std::mt19937 random(8);
  const SnapshotHeader header = random_header(20, random);
  const std::string path = file("other.h5");
  write_snapshot(path, header, 2, random, false);

  SnapshotHeader other_scene = header;
  other_scene.scene += "# changed\n";
  EXPECT_NE(error_message([&] {
              SnapshotWriter::resume(path, other_scene, kAllFields, 1);
            }).find("was written for another scene"),
            std::string::npos);
  EXPECT_NE(error_message([&] { SnapshotWriter::resume(path, header, kFieldX, 1); })
                .find("holds the fields x, v, F, C, stress, J, von_mises, energy_density, Jp, plastic_strain, this run "
                      "writes x"),
            std::string::npos);
  EXPECT_EQ(error_message([&] { SnapshotWriter::resume(path, header, kAllFields, 3); }),
            "snapshot " + partial_path(path) + ": holds 2 complete frames, the resume needs 3");
  EXPECT_EQ(error_message([&] { SnapshotWriter::resume(file("none.h5"), header, kAllFields, 0); }),
            "snapshot " + partial_path(file("none.h5")) + ": no such file");
}

TEST_F(Snapshot, ReaderRejectsAnHdf5FileThatIsNotASnapshot) {
  const std::string path = file("foreign.h5");
  {
    io::hdf5::File foreign = io::hdf5::File::create(path, "test file");
    foreign.write_dataset("data", {2}, std::vector<double>{1.0, 2.0});
    foreign.close();
  }
  EXPECT_EQ(error_message([&] { SnapshotReader reader(path); }),
            "snapshot " + path + ": not a romp snapshot: root attribute format is missing");
  {
    io::hdf5::File other = io::hdf5::File::open(path, io::hdf5::Mode::ReadWrite, "test file");
    other.write_attribute("format", "romp-model");
    other.close();
  }
  EXPECT_EQ(error_message([&] { SnapshotReader reader(path); }),
            "snapshot " + path +
                ": not a romp snapshot: root attribute format is \"romp-model\", expected "
                "\"romp-snapshot\"");
}

TEST_F(Snapshot, ReaderRejectsANewerFormatVersion) {
  std::mt19937 random(9);
  const std::string path = file("newer.h5");
  write_snapshot(path, random_header(5, random), 1, random);
  {
    io::hdf5::File file = io::hdf5::File::open(path, io::hdf5::Mode::ReadWrite, "test file");
    file.write_attribute("format_version", std::int64_t(2));
    file.close();
  }
  EXPECT_NE(error_message([&] { SnapshotReader reader(path); }).find("format_version 2 is not one this romp reads"),
            std::string::npos);
}

TEST_F(Snapshot, ReaderRejectsATruncatedFile) {
  std::mt19937 random(10);
  const std::string path = file("truncated.h5");
  write_snapshot(path, random_header(200, random), 2, random);
  std::filesystem::resize_file(path, std::filesystem::file_size(path) / 2);
  const std::string message = error_message([&] {
    const SnapshotReader reader(path);
    reader.read_frame(1);
  });
  EXPECT_EQ(message.rfind("snapshot " + path + ": ", 0), 0u) << message;
  EXPECT_NE(message.find("truncated"), std::string::npos) << message;
}

TEST_F(Snapshot, AMissingDatasetIsNamedWithItsFile) {
  std::mt19937 random(11);
  const std::string path = file("missing.h5");
  write_snapshot(path, random_header(5, random), 2, random);
  {
    io::hdf5::File file = io::hdf5::File::open(path, io::hdf5::Mode::ReadWrite, "test file");
    file.remove("/frames/000001/v");
    file.close();
  }
  const SnapshotReader reader(path);
  EXPECT_NO_THROW(reader.read_frame(0));
  EXPECT_EQ(error_message([&] { reader.read_frame(1); }), "snapshot " + path + ": dataset /frames/000001/v: missing");
  EXPECT_EQ(error_message([&] { reader.read_frame(2); }), "snapshot " + path + ": frame 2 does not exist (2 frames)");
}

}  // namespace
}  // namespace romp::io::testing
