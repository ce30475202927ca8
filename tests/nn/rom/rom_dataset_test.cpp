// Sweep folders as training data: the split by member, each frame linked to the next, the encoder's points,
// and unusable folders rejected with the file and the reason named.
#include "nn/rom/rom_dataset.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "nn/io/hdf5_file.h"
#include "tests/nn/rom/twisted_bar.h"
#include "tests/support/scratch_folder.h"

namespace romp::nn::rom {
namespace {

TEST(RomDataset, SplitsByMemberAndLinksEachFrameToTheNext) {
  const test::ScratchFolder folder;
  const test::TwistedBar bar;
  bar.write(folder.path());
  const RomDataset data = load_rom_dataset(folder.path().string(), {0, 0, torch::kCPU});
  const std::int64_t points = bar.nx * bar.ny * bar.nz;
  ASSERT_EQ(data.members.size(), std::size_t(bar.members));
  EXPECT_EQ(data.parameter_names, std::vector<std::string>{"twist"});
  EXPECT_TRUE(data.members[2].test && !data.members[3].test);
  EXPECT_EQ(data.particle_count(), points);
  EXPECT_EQ(data.train.size(), std::int64_t(bar.members - bar.test_members.size()) * bar.frames);
  EXPECT_EQ(data.test.size(), std::int64_t(bar.test_members.size()) * bar.frames);
  EXPECT_EQ(data.train.F.sizes(), (std::vector<std::int64_t>{data.train.size(), points, 3, 3}));
  EXPECT_EQ(data.encoder_indices.size(0), points);

  // Frame 0 of the first training member is the reference; its last frame has no successor.
  EXPECT_TRUE(torch::equal(data.train.x[0], data.X));
  EXPECT_EQ(data.train.next[0].item<std::int64_t>(), 1);
  const std::int64_t last = bar.frames - 1;
  EXPECT_EQ(data.train.next[last].item<std::int64_t>(), last);
  EXPECT_EQ(data.train.has_next[last].item<float>(), 0.0f);
  EXPECT_FLOAT_EQ(data.train.dt[0].item<float>(), float(bar.end_time / (bar.frames - 1)));

  // The velocity target is the frames' own forward difference (x_{n+1} − x_n)/Δt, zero for a last frame;
  // in every member (a member's first row follows the last row of the one before).
  for (const SnapshotSet* set : {&data.train, &data.test}) {
    const torch::Tensor x = set->x;
    const torch::Tensor expected =
        (x.index_select(0, set->next) - x) / set->dt.view({-1, 1, 1}) * set->has_next.view({-1, 1, 1});
    EXPECT_TRUE(torch::allclose(set->frame_velocity, expected, 1e-5, 1e-6));
    EXPECT_GT(set->frame_velocity.abs().max().item<float>(), 0.1f);
  }
}

TEST(RomDataset, EncoderPointsAreADeterministicIncreasingSubset) {
  const test::ScratchFolder folder;
  test::TwistedBar bar;
  bar.members = 2;
  bar.test_members = {};
  bar.frames = 2;
  bar.write(folder.path());
  const RomDataset a = load_rom_dataset(folder.path().string(), {100, 4, torch::kCPU});
  const RomDataset b = load_rom_dataset(folder.path().string(), {100, 4, torch::kCPU});
  ASSERT_EQ(a.encoder_indices.size(0), 100);
  EXPECT_TRUE(torch::equal(a.encoder_indices, b.encoder_indices));
  EXPECT_TRUE((a.encoder_indices.slice(0, 1) > a.encoder_indices.slice(0, 0, -1)).all().item<bool>());
  EXPECT_EQ(a.test.size(), 0);
}

TEST(RomDataset, SnapshotWithoutDeformationGradientsIsRejectedNamingIt) {
  const test::ScratchFolder folder;
  test::TwistedBar bar;
  bar.members = 2;
  bar.frames = 2;
  bar.write(folder.path());
  {
    io::hdf5::File file = io::hdf5::File::open(folder.file("member_000001.h5"), io::hdf5::Mode::ReadWrite, "snapshot");
    file.write_attribute("fields", std::vector<std::string>{"x", "v"});
  }
  const std::string message =
      test::error_message<io::UnusableFileError>([&] { load_rom_dataset(folder.path().string(), {}); });
  EXPECT_NE(message.find("member_000001.h5"), std::string::npos) << message;
  EXPECT_NE(message.find("lacks \"F\""), std::string::npos) << message;
}

// A manifest whose member is an array nested 200,000 deep once crashed train-rom while the error was
// written: it is refused, naming the member by its place.
TEST(RomDataset, ADeeplyNestedMemberIsRefusedByItsPlace) {
  const test::ScratchFolder folder;
  const int depth = 200000;
  std::ofstream(folder.file("manifest.json"))
      << R"({"format": "romp-sweep", "format_version": 1, "parameters": ["a"], "members": [)" << std::string(depth, '[')
      << std::string(depth, ']') << "]}";
  const std::string message =
      test::error_message<io::UnusableFileError>([&] { load_rom_dataset(folder.path().string(), {}); });
  EXPECT_NE(message.find("manifest.json: members[0] (a JSON array)"), std::string::npos) << message;
  EXPECT_LT(message.size(), 500u) << "the error quotes the member";
}

// Every manifest no sweep could have written is an unusable input (romp exits 3), named by what is wrong.
TEST(RomDataset, ManifestsOfTheWrongFormOrContentAreUnusableInputs) {
  const std::string head = R"({"format": "romp-sweep", "format_version": 1, "parameters": ["a"], )";
  const std::pair<std::string, std::string> cases[] = {
      {"{", "not valid JSON"},
      {R"({"format": "romp-snapshot", "format_version": 1})", "format is not \"romp-sweep\""},
      {R"({"format": "romp-sweep", "format_version": 99})", "format_version 99"},
      {head + R"("members": []})", "lists no members"},
      {head + R"("members": [{"index": 0, "values": {"a": 1}, "split": "both", "snapshot": "m.h5"}]})",
       "members[0] (a JSON object): split is \"both\""},
      {head + R"("members": [{"index": 0, "values": {}, "split": "train", "snapshot": "m.h5"}]})", "members[0]"},
  };
  for (const auto& [manifest, expected] : cases) {
    const test::ScratchFolder folder;
    folder.write("manifest.json", manifest);
    const std::string message =
        test::error_message<io::UnusableFileError>([&] { load_rom_dataset(folder.path().string(), {}); });
    EXPECT_NE(message.find(expected), std::string::npos) << manifest << "\n" << message;
  }
}

TEST(RomDataset, FolderWithoutManifestIsRejected) {
  const test::ScratchFolder folder;
  const std::string message =
      test::error_message<io::UnusableFileError>([&] { load_rom_dataset(folder.path().string(), {}); });
  EXPECT_NE(message.find("no manifest.json"), std::string::npos) << message;
  EXPECT_NE(message.find(folder.path().string()), std::string::npos) << message;
}

}  // namespace
}  // namespace romp::nn::rom
