// romp::Error and the checks that throw it with the failing place and expression.
#pragma once

#include <stdexcept>
#include <string>

namespace romp {

// Every failure romp reports is a romp::Error: a testable exception, never exit() or abort().
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
  Error(const std::string& message, const char* file, int line, const char* expression);

  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& expression() const { return expression_; }

 private:
  std::string file_;
  int line_ = 0;
  std::string expression_;
};

}  // namespace romp

// ROMP_CHECK(condition, message): throws romp::Error naming the place, the condition and why it
// matters. `message` is any expression convertible to std::string, evaluated only on failure.
#define ROMP_CHECK(condition, message)                                                           \
  do {                                                                                           \
    if (!(condition)) throw ::romp::Error(std::string(message), __FILE__, __LINE__, #condition); \
  } while (false)
