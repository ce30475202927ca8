// The romp command's exit codes (README "Exit codes"), shared by main and the commands. An interrupted
// run exits with run::kExitInterrupted (130, host/run/interrupt.h).
#pragma once

namespace romp::cli {

inline constexpr int kExitDone = 0;
inline constexpr int kExitRunFailed = 1;  // the machine's fault, not the input's
inline constexpr int kExitBadArguments = 2;
inline constexpr int kExitInvalidInput = 3;  // a scene or input file that cannot be used
inline constexpr int kExitNonFinite = 4;     // the simulation went non-finite
inline constexpr int kExitSweepMembersFailed = 5;

}  // namespace romp::cli
