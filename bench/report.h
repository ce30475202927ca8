// Writes a romp-bench run as CSV (one row per measurement) and JSON (everything, with the environment).
#pragma once

#include <string>

#include "bench/harness.h"

namespace romp::bench {

// Writes <directory>/<stem>.csv and <directory>/<stem>.json atomically (temporary name, then rename).
void write_report(const Context& context, const std::string& directory, const std::string& stem);

}  // namespace romp::bench
