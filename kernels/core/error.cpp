// Formats romp::Error messages as "file:line: message [expression]".
#include "kernels/core/error.h"

namespace romp {
namespace {

std::string place_message(const std::string& message, const char* file, int line, const char* expression) {
  return std::string(file) + ":" + std::to_string(line) + ": " + message + " [" + expression + "]";
}

}  // namespace

Error::Error(const std::string& message, const char* file, int line, const char* expression)
    : std::runtime_error(place_message(message, file, line, expression)),
      file_(file),
      line_(line),
      expression_(expression) {}

}  // namespace romp
