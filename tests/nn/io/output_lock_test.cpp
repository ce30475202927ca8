// OutputLock: one claim on an output at a time; the second is refused with the output and holder named.
#include "nn/io/output_lock.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <optional>
#include <string>

#include "kernels/core/error.h"
#include "tests/support/scratch_folder.h"

namespace romp::io {
namespace {

namespace fs = std::filesystem;

TEST(OutputLock, ASecondClaimIsRefusedUntilTheFirstEnds) {
  const test::ScratchFolder folder;
  const std::string output = (folder.path() / "runs" / "cube.h5").string();  // its folder does not exist yet
  std::optional<OutputLock> first(std::in_place, output);
  EXPECT_TRUE(fs::exists(output + ".lock"));
  try {
    OutputLock second(output);
    FAIL() << "a second claim was granted";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(output + " is being written by process " + std::to_string(getpid())), std::string::npos)
        << message;
  }
  first.reset();
  EXPECT_FALSE(fs::exists(output + ".lock")) << "the lock file outlives the claim";
  EXPECT_NO_THROW(OutputLock again(output));
}

}  // namespace
}  // namespace romp::io
