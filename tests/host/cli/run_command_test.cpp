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

// --tracers-by says what carries a full-order run's --output-points: it needs them, has no meaning for a
// reduced run (which decodes them), and takes one of its two words.
TEST(RunCommand, TracersByNeedsOutputPointsOfAFullOrderRun) {
  test::ScratchFolder folder;
  for (const char* name : {"scene.toml", "model.h5", "points.h5"}) folder.write(name, "x");
  const std::string run = "run " + folder.file("scene.toml") + " ";
  const std::string points = "--output-points " + folder.file("points.h5") + " ";
  const auto parsed = [](const std::string& line) {
    CLI::App app;
    RunCommandOptions options;
    add_run_command(app, options, "");
    app.parse(line, false);
    return options.run.tracers_by;
  };
  EXPECT_EQ(parsed(run + points + "--tracers-by grid"), engine::TracerCarrier::Grid);
  EXPECT_EQ(parsed(run + points + "--tracers-by material"), engine::TracerCarrier::Material);
  EXPECT_EQ(parsed(run + points), engine::TracerCarrier::Material);
  EXPECT_THROW(parsed(run + "--tracers-by grid"), CLI::RequiresError);
  EXPECT_THROW(parsed(run + points + "--rom " + folder.file("model.h5") + " --tracers-by grid"), CLI::ExcludesError);
  EXPECT_THROW(parsed(run + points + "--tracers-by particles"), CLI::ValidationError);
}

}  // namespace
}  // namespace romp::cli
