// Law files: a round trip keeps every weight and the training record; damaged files are rejected
// with the file and the object named.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "kernels/core/error.h"
#include "nn/io/hdf5_file.h"
#include "nn/nclaw/law_file.h"
#include "tests/support/scratch_folder.h"

namespace romp::nn::nclaw {
namespace {

NeuralLaws random_laws() { return seeded_laws(7, torch::kFloat32); }

// The message of the io::UnusableFileError (an invalid input: romp exits 3) that reading `path` throws ("" when
// it reads); any other error escapes and fails the test.
std::string read_error(const std::string& path) {
  try {
    read_law_file(path);
  } catch (const io::UnusableFileError& error) {
    return error.what();
  }
  return "";
}

TEST(LawFile, RoundTripKeepsWeightsAndTrainingRecord) {
  const romp::test::ScratchFolder folder;
  NeuralLaws laws = random_laws();
  const std::string path = folder.file("law.h5");
  write_law_file(path, laws, {"runs/jelly.h5", 1000, {3.5, 2.25, 1.0}, 2.5e-4});
  LawFile read = read_law_file(path);
  const std::vector<torch::Tensor> expected = laws.parameters(), result = read.laws.parameters();
  ASSERT_EQ(result.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) EXPECT_TRUE(torch::equal(result[i], expected[i])) << "weight " << i;
  EXPECT_EQ(read.laws.plastic->step(), laws.plastic->step());
  EXPECT_EQ(read.training.trajectory, "runs/jelly.h5");
  EXPECT_EQ(read.training.steps, 1000);
  EXPECT_EQ(read.training.loss, (std::vector<double>{3.5, 2.25, 1.0}));
  EXPECT_EQ(read.training.reconstruction_error, 2.5e-4);
  const torch::Tensor F = torch::eye(3).reshape({9, 1}) + 0.1 * torch::randn({9, 16});
  EXPECT_TRUE(torch::equal(read.laws.elastic->forward(F), laws.elastic->forward(F)));
}

TEST(LawFile, RejectsDamagedFilesNamingWhatIsWrong) {
  const romp::test::ScratchFolder folder;
  const std::string path = folder.file("law.h5");
  write_law_file(path, random_laws(), {"gt.h5", 10, {1.0}, 0.0});

  EXPECT_NE(read_error(folder.write("text.h5", "not HDF5")).find("text.h5"), std::string::npos);
  {
    io::hdf5::File file = io::hdf5::File::open(path, io::hdf5::Mode::ReadWrite, "neural law");
    file.write_attribute("width", std::int64_t(0));
  }
  EXPECT_NE(read_error(path).find("width is 0, allowed only 64"), std::string::npos) << read_error(path);

  write_law_file(path, random_laws(), {"gt.h5", 10, {1.0}, 0.0});
  {
    io::hdf5::File file = io::hdf5::File::open(path, io::hdf5::Mode::ReadWrite, "neural law");
    file.remove("plastic/weight_1");
  }
  EXPECT_NE(read_error(path).find("/plastic/weight_1"), std::string::npos) << read_error(path);

  write_law_file(path, random_laws(), {"gt.h5", 10, {1.0}, 0.0});
  {
    io::hdf5::File file = io::hdf5::File::open(path, io::hdf5::Mode::ReadWrite, "neural law");
    std::vector<double> weights(9 * 64, 0.0);
    weights[5] = std::nan("");
    file.remove("elastic/weight_2");
    file.write_dataset("elastic/weight_2", {9, 64}, weights);
  }
  EXPECT_NE(read_error(path).find("/elastic/weight_2: holds a non-finite weight"), std::string::npos)
      << read_error(path);

  write_law_file(path, random_laws(), {"gt.h5", 10, {1.0}, 0.0});
  {
    io::hdf5::File file = io::hdf5::File::open(path, io::hdf5::Mode::ReadWrite, "neural law");
    file.write_attribute("format", "romp-snapshot");
  }
  EXPECT_NE(read_error(path).find("root attribute format is \"romp-snapshot\", expected \"romp-neural-law\""),
            std::string::npos)
      << read_error(path);
}

}  // namespace
}  // namespace romp::nn::nclaw
