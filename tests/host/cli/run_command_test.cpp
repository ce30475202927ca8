// The run command's options: combinations a run cannot honour are bad arguments (CLI11's errors, exit 2),
// refused before a scene is read.
#include "host/cli/run_command.h"

#include <gtest/gtest.h>

#include <string>

#include "tests/support/scratch_folder.h"

namespace romp::cli {
namespace {

// --resume continues a full-order run from its checkpoint, which holds neither a reduced state nor tracers.
TEST(RunCommand, ResumeIsRefusedWithAReducedRunOrOutputPoints) {
  test::ScratchFolder folder;
  for (const char* name : {"scene.toml", "model.h5", "points.h5"}) folder.write(name, "x");  // they must exist
  for (const std::string option : {"--rom", "--output-points"}) {
    CLI::App app;
    RunCommandOptions options;
    add_run_command(app, options, "");
    const std::string file = folder.file(option == "--rom" ? "model.h5" : "points.h5");
    EXPECT_THROW(app.parse("run " + folder.file("scene.toml") + " " + option + " " + file + " --resume", false),
                 CLI::ExcludesError)
        << option;
  }
}

}  // namespace
}  // namespace romp::cli
