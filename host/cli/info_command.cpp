// `romp info`.
#include "host/cli/info_command.h"

#include <fmt/format.h>

#include "host/build_info.h"
#include "host/cli/exit_codes.h"
#include "host/cli/info_report.h"
#include "kernels/core/device.h"
#include "nn/torch_info.h"

namespace romp::cli {

CLI::App* add_info_command(CLI::App& app) {
  return app.add_subcommand("info", "Version, commit, build configuration and the devices found");
}

int info_command() {
  fmt::print("{}", info_report(build_info(), probe_cuda(), nn::torch_info()));
  return kExitDone;
}

}  // namespace romp::cli
