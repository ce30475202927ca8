// libFuzzer harness: the scene formula evaluator (host/scene/expression.h) on arbitrary text, with two
// parameters defined. Any input must either evaluate or throw romp::Error; a crash, a sanitizer report
// or a hang is a bug (issue #32: a formula nested 30,000 deep overflowed the stack).
#include <cstddef>
#include <cstdint>
#include <string>

#include "host/scene/expression.h"
#include "kernels/core/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    romp::scene::evaluate_expression(text, {{"dx", 0.02}, {"speed", 3.0}});
  } catch (const romp::Error&) {
  }
  return 0;
}
