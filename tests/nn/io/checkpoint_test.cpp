// Checkpoints: the state a resumed run starts from comes back bit for bit, and bad files say why.
#include <gtest/gtest.h>

#include <filesystem>
#include <limits>
#include <random>

#include "kernels/core/error.h"
#include "nn/io/checkpoint.h"
#include "nn/io/hdf5_file.h"
#include "nn/io/snapshot_layout.h"
#include "tests/nn/io/io_test_support.h"

namespace romp::io::testing {
namespace {

using CheckpointFile = IoTest;

Checkpoint random_checkpoint(std::int64_t n, std::mt19937& random) {
  Checkpoint checkpoint;
  // 0.1 + 0.2 is not a short decimal: it must come back exactly.
  checkpoint.state = random_frame(n, 0.1 + 0.2, 123456789012345, random);
  checkpoint.frame = 12;
  checkpoint.tag = "[scene]\nname = \"resumable\"\n";
  return checkpoint;
}

TEST_F(CheckpointFile, RoundTripsBitwise) {
  std::mt19937 random(21);
  Checkpoint checkpoint = random_checkpoint(1000, random);
  checkpoint.state.v[7] = -0.0f;
  checkpoint.state.F[8] = std::numeric_limits<float>::denorm_min();
  const std::string path = checkpoint_path(file("run.h5"));
  write_checkpoint(path, checkpoint);
  const Checkpoint back = read_checkpoint(path);
  EXPECT_EQ(back.frame, checkpoint.frame);
  EXPECT_EQ(back.tag, checkpoint.tag);
  EXPECT_EQ(back.state.time, checkpoint.state.time);
  EXPECT_EQ(back.state.step, checkpoint.state.step);
  EXPECT_EQ(back.state.x.size(), 3000u);
  EXPECT_TRUE(bitwise_equal(back.state.x, checkpoint.state.x));
  EXPECT_TRUE(bitwise_equal(back.state.v, checkpoint.state.v));
  EXPECT_TRUE(bitwise_equal(back.state.F, checkpoint.state.F));
  EXPECT_TRUE(bitwise_equal(back.state.C, checkpoint.state.C));
}

TEST_F(CheckpointFile, ReplacingOneLeavesOnlyTheNewFile) {
  std::mt19937 random(22);
  const std::string path = file("run.h5.checkpoint");
  write_checkpoint(path, random_checkpoint(10, random));
  Checkpoint later = random_checkpoint(10, random);
  later.frame = 13;
  write_checkpoint(path, later);
  EXPECT_EQ(read_checkpoint(path).frame, 13);
  EXPECT_EQ(folder_contents(), (std::vector<std::string>{"run.h5.checkpoint"}));
}

TEST_F(CheckpointFile, InconsistentStateIsRejectedAndNothingIsWritten) {
  std::mt19937 random(23);
  Checkpoint checkpoint = random_checkpoint(10, random);
  checkpoint.state.F.resize(80);
  EXPECT_THROW(write_checkpoint(file("bad.checkpoint"), checkpoint), Error);
  EXPECT_TRUE(folder_contents().empty());
}

// A checkpoint with a non-finite value (its checksums intact: written so) is not a state to resume from:
// refused as an unusable input (exit 3), naming the file, the dataset and the value.
TEST_F(CheckpointFile, NonFiniteValuesAreRefused) {
  std::mt19937 random(29);
  Checkpoint checkpoint = random_checkpoint(10, random);
  checkpoint.state.v[7] = std::numeric_limits<float>::quiet_NaN();
  const std::string path = file("nan.checkpoint");
  write_checkpoint(path, checkpoint);
  try {
    read_checkpoint(path);
    ADD_FAILURE() << "no error";
  } catch (const io::UnusableFileError& error) {
    EXPECT_EQ(std::string(error.what()),
              "checkpoint " + path + ": dataset /v: value 7 of 30 is nan: not a state to resume from");
  }
}

TEST_F(CheckpointFile, ReadErrorsNameTheFile) {
  const std::string missing = file("none.checkpoint");
  try {
    read_checkpoint(missing);
    ADD_FAILURE() << "no error";
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()), "checkpoint " + missing + ": no such file");
  }
  const std::string foreign = file("foreign.checkpoint");
  io::hdf5::File::create(foreign, "test file").close();
  try {
    read_checkpoint(foreign);
    ADD_FAILURE() << "no error";
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()),
              "checkpoint " + foreign + ": not a romp checkpoint: root attribute format is missing");
  }
}

}  // namespace
}  // namespace romp::io::testing
