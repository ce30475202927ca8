// The romp command line: one entry point for every mode, one file per command beside this one. Exit
// codes (README "Exit codes", exit_codes.h): 0 done, 1 run failed, 2 bad arguments, 3 invalid scene or
// input file, 4 simulation went non-finite, 5 sweep members failed, 130 interrupted (resumable with
// --resume).
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <csignal>
#include <exception>

#include "host/backend_selection.h"
#include "host/cli/check_command.h"
#include "host/cli/compare_command.h"
#include "host/cli/exit_codes.h"
#include "host/cli/global_options.h"
#include "host/cli/info_command.h"
#include "host/cli/learn_law_command.h"
#include "host/cli/run_command.h"
#include "host/cli/sweep_command.h"
#include "host/cli/totals_command.h"
#include "host/cli/train_rom_command.h"
#include "host/scene/toml_reader.h"
#include "kernels/core/error.h"
#include "nn/io/hdf5_file.h"

int main(int argc, char** argv) {
  // A reader that closes the pipe (`romp info | head -1`) makes a write fail with EPIPE, an error romp
  // reports, instead of killing the process mid-run with SIGPIPE.
  std::signal(SIGPIPE, SIG_IGN);
  using namespace romp::cli;
  CLI::App app{"romp: material point method with neural reduced-order models"};
  app.require_subcommand(1);
  GlobalOptions global;
  add_global_options(app, global);

  const CLI::App* info = add_info_command(app);
  CheckOptions check_options;
  const CLI::App* check = add_check_command(app, check_options);
  RunCommandOptions run_options;
  const CLI::App* run = add_run_command(app, run_options, ROMP_DEFAULT_SCENE);
  SweepCommandOptions sweep_options;
  const CLI::App* sweep = add_sweep_command(app, sweep_options);
  CompareOptions compare_options;
  const CLI::App* compare = add_compare_command(app, compare_options);
  TotalsOptions totals_options;
  const CLI::App* totals = add_totals_command(app, totals_options);
  LearnLawOptions learn_law_options;
  const CLI::App* learn_law = add_learn_law_command(app, learn_law_options);
  TrainRomOptions train_rom_options;
  const CLI::App* train_rom = add_train_rom_command(app, train_rom_options);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    return app.exit(error) == 0 ? kExitDone : kExitBadArguments;
  }
  spdlog::set_level(spdlog::level::from_str(global.log_level));

  try {
    const romp::DeviceChoice choice = romp::parse_device_choice(global.device);
    if (info->parsed()) return info_command();
    if (check->parsed()) return check_command(check_options);
    if (run->parsed()) return run_command(choice, global.threads, run_options);
    if (sweep->parsed()) return sweep_command(global, sweep_options);
    if (compare->parsed()) return compare_command(compare_options);
    if (totals->parsed()) return totals_command(totals_options);
    if (learn_law->parsed()) return learn_law_command(choice, global.threads, learn_law_options);
    if (train_rom->parsed()) return train_rom_command(choice, global.threads, train_rom_options);
    throw romp::Error("no command was run");  // require_subcommand(1) makes this unreachable
  } catch (const CLI::ParseError& error) {
    return app.exit(error) == 0 ? kExitDone : kExitBadArguments;
  } catch (const romp::scene::SceneError& error) {
    spdlog::error("{}", error.what());
    return kExitInvalidInput;
  } catch (const romp::io::UnusableFileError& error) {
    spdlog::error("{}", error.what());
    return kExitInvalidInput;
  } catch (const romp::engine::NonFiniteError& error) {
    spdlog::error("{}", error.what());
    return kExitNonFinite;
  } catch (const std::exception& error) {
    spdlog::error("{}", error.what());
    return kExitRunFailed;
  }
}
