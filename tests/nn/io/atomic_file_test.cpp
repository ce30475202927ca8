// AtomicFile: the target is replaced whole or not at all, and no temporary survives.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "kernels/core/error.h"
#include "nn/io/atomic_file.h"
#include "tests/nn/io/io_test_support.h"

namespace romp::io::testing {
namespace {

using AtomicFileTest = IoTest;

TEST_F(AtomicFileTest, CommitReplacesTheTarget) {
  const std::string path = file("a.txt");
  write_file_atomically(path, "old");
  write_file_atomically(path, std::string("new\0bytes", 9));
  EXPECT_EQ(read_file(path), std::string("new\0bytes", 9));
  EXPECT_EQ(folder_contents(), (std::vector<std::string>{"a.txt"}));
}

TEST_F(AtomicFileTest, CreatesMissingFolders) {
  const std::string path = file("deep/er/a.txt");
  write_file_atomically(path, "x");
  EXPECT_EQ(read_file(path), "x");
}

TEST_F(AtomicFileTest, AnAbandonedWriteLeavesTheTargetAndNoTemporary) {
  const std::string path = file("a.txt");
  write_file_atomically(path, "old");
  try {
    AtomicFile target(path);
    EXPECT_EQ(target.temp_path(), path + ".tmp-" + std::to_string(::getpid()));
    std::ofstream(target.temp_path()) << "half of the new cont";
    throw std::runtime_error("the writer failed");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(read_file(path), "old");
  EXPECT_EQ(folder_contents(), (std::vector<std::string>{"a.txt"}));
}

TEST_F(AtomicFileTest, AFailedWriteIsAnErrorAndLeavesNoTemporary) {
  std::ofstream(file("plain")) << "a file, not a folder";
  EXPECT_THROW(write_file_atomically(file("plain/a.txt"), "x"), Error);
  // Committing a temporary that was never written fails too, and leaves nothing behind.
  {
    AtomicFile target(file("b.txt"));
    EXPECT_THROW(target.commit(), Error);
    EXPECT_FALSE(target.committed());
  }
  EXPECT_EQ(folder_contents(), (std::vector<std::string>{"plain"}));
}

}  // namespace
}  // namespace romp::io::testing
