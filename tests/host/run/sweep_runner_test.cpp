// romp sweep: one snapshot per member, a manifest with the split, finished members skipped on a
// second run, and ranks that share the members without overlap.
#include "host/run/sweep_runner.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "nn/io/snapshot_reader.h"
#include "tests/support/scratch_folder.h"

namespace romp::run {
namespace {

namespace fs = std::filesystem;

const char* const kSweepScene = R"(
[parameters]
speed = 1.0
[domain]
size = [1.0, 1.0, 1.0]
dx = 0.1
[time]
end = 0.01
frame_rate = 200
dt = 1e-3
[boundary]
wall_cells = 2
[materials.jelly]
preset = "jelly"
[[objects]]
velocity = ["speed", 0, 0]
shape = { type = "box", center = [0.5, 0.5, 0.5], size = [0.3, 0.3, 0.3] }
sampling = { per_cell = 1 }
[sweep]
method = "grid"
test_fraction = 0.34
[sweep.parameters.speed]
range = [0.0, 2.0]
count = 3
)";

class SweepRunner : public ::testing::Test {
 protected:
  void SetUp() override { scene_ = folder_.write("sweep.toml", kSweepScene); }
  void TearDown() override {
    unsetenv("OMPI_COMM_WORLD_RANK");
    unsetenv("OMPI_COMM_WORLD_SIZE");
  }
  SweepOptions options(const std::string& out) const {
    SweepOptions o;
    o.output_dir = folder_.file(out);
    o.jobs = 2;
    o.run_arguments = {"--device", "cpu", "--threads", "1", "--log-level", "warn"};
    o.executable = ROMP_EXECUTABLE;
    return o;
  }
  test::ScratchFolder folder_;
  std::string scene_;
};

// --set: a declared parameter the sweep leaves alone takes the given value in every member (e.g. a coarser
// dx to shrink a paper's sweep); a swept one cannot be set.
TEST_F(SweepRunner, SetGivesEveryMemberTheValueAndRefusesASweptParameter) {
  std::string text = kSweepScene;
  text.replace(text.find("speed = 1.0"), 11, "speed = 1.0\nwidth = 0.3");
  text.replace(text.find("size = [0.3, 0.3, 0.3]"), 22, "size = [\"width\", \"width\", \"width\"]");
  const std::string scene = folder_.write("sweep_width.toml", text);
  SweepOptions o = options("set");
  o.overrides = {{"width", 0.2}};
  const SweepSummary summary = run_sweep(scene, o);
  ASSERT_TRUE(summary.failed.empty()) << summary.failed.front();
  nlohmann::json manifest;
  std::ifstream(fs::path(o.output_dir) / "manifest.json") >> manifest;
  ASSERT_EQ(manifest["members"].size(), 3u);
  for (const auto& member : manifest["members"]) {
    const io::SnapshotReader reader((fs::path(o.output_dir) / member["snapshot"].get<std::string>()).string());
    const io::SnapshotHeader& header = reader.header();
    const auto width = std::find(header.parameter_names.begin(), header.parameter_names.end(), "width");
    ASSERT_NE(width, header.parameter_names.end());
    EXPECT_EQ(header.parameter_values[std::size_t(width - header.parameter_names.begin())], 0.2);
  }
  o.output_dir = folder_.file("swept");
  o.overrides = {{"speed", 3.0}};
  EXPECT_THROW(run_sweep(scene, o), scene::SceneError);
}

TEST_F(SweepRunner, RunsEveryMemberOnceAndSkipsFinishedOnesOnResume) {
  const SweepOptions o = options("out");
  const SweepSummary first = run_sweep(scene_, o);
  EXPECT_EQ(first.members, 3);
  EXPECT_EQ(first.ran, 3);
  EXPECT_TRUE(first.failed.empty()) << first.failed.front();

  nlohmann::json manifest;
  std::ifstream(fs::path(o.output_dir) / "manifest.json") >> manifest;
  ASSERT_EQ(manifest["members"].size(), 3u);
  int tests = 0;
  for (const auto& member : manifest["members"]) {
    const fs::path snapshot = fs::path(o.output_dir) / member["snapshot"].get<std::string>();
    ASSERT_TRUE(fs::exists(snapshot)) << snapshot;
    const io::SnapshotReader reader(snapshot.string());
    ASSERT_EQ(reader.header().parameter_names, std::vector<std::string>{"speed"});
    EXPECT_EQ(reader.header().parameter_values[0], member["values"]["speed"].get<double>());
    tests += member["split"] == "test";
  }
  EXPECT_EQ(tests, 1);  // round(0.34 × 3)

  fs::remove(fs::path(o.output_dir) / (member_stem(1) + ".h5"));
  const SweepSummary second = run_sweep(scene_, o);
  EXPECT_EQ(second.finished_before, 2);
  EXPECT_EQ(second.ran, 1);
}

TEST_F(SweepRunner, RanksTakeDisjointMembers) {
  const SweepOptions o = options("ranks");
  std::int64_t assigned = 0;
  for (int rank = 0; rank < 2; ++rank) {
    setenv("OMPI_COMM_WORLD_RANK", std::to_string(rank).c_str(), 1);
    setenv("OMPI_COMM_WORLD_SIZE", "2", 1);
    const SweepSummary s = run_sweep(scene_, o);
    EXPECT_EQ(s.rank, rank);
    EXPECT_EQ(s.finished_before, 0);  // rank 1 never touches rank 0's members
    EXPECT_EQ(s.ran, s.assigned);
    assigned += s.assigned;
  }
  EXPECT_EQ(assigned, 3);
  for (std::int64_t m = 0; m < 3; ++m) EXPECT_TRUE(fs::exists(fs::path(o.output_dir) / (member_stem(m) + ".h5")));
}

}  // namespace
}  // namespace romp::run
