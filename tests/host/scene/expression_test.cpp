// Scene formulas: arithmetic, precedence, functions, parameters and located errors.
#include "host/scene/expression.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "tests/support/scratch_folder.h"

namespace romp::scene {
namespace {

TEST(Expression, FollowsMathematicalPrecedence) {
  EXPECT_DOUBLE_EQ(evaluate_expression("1 + 2 * 3", {}), 7.0);
  EXPECT_DOUBLE_EQ(evaluate_expression("(1 + 2) * 3", {}), 9.0);
  EXPECT_DOUBLE_EQ(evaluate_expression("-2^2", {}), -4.0);
  EXPECT_DOUBLE_EQ(evaluate_expression("2^3^2", {}), 512.0);
  EXPECT_DOUBLE_EQ(evaluate_expression("8 / 4 / 2", {}), 1.0);
  EXPECT_DOUBLE_EQ(evaluate_expression("1.5e3 - .5", {}), 1499.5);
}

TEST(Expression, ReadsParametersAndFunctions) {
  const ParameterValues p{{"speed", 2.0}, {"angle", 30.0}};
  EXPECT_NEAR(evaluate_expression("speed * cos(radians(angle))", p), std::sqrt(3.0), 1e-15);
  EXPECT_NEAR(evaluate_expression("atan2(1, 1)", p), std::atan(1.0), 1e-15);
  EXPECT_DOUBLE_EQ(evaluate_expression("max(speed, 3) + min(1, pow(2, 3))", p), 4.0);
  EXPECT_NEAR(evaluate_expression("degrees(pi)", p), 180.0, 1e-12);
}

TEST(Expression, ErrorsNameTheColumnAndTheProblem) {
  const ParameterValues p{{"speed", 2.0}};
  auto message = [&](const std::string& text) { return test::error_message([&] { evaluate_expression(text, p); }); };
  EXPECT_NE(message("sped * 2").find("unknown name 'sped' (parameters: speed)"), std::string::npos);
  EXPECT_EQ(message("speed * 2"), "(no error)");
  EXPECT_NE(message("1 +").find("ends where a value is expected"), std::string::npos);
  EXPECT_NE(message("(1 + 2").find("expected ')'"), std::string::npos);
  EXPECT_NE(message("2 3").find("column 3: unexpected '3'"), std::string::npos);
  EXPECT_NE(message("sin(1, 2)").find("sin() takes 1 argument, got 2"), std::string::npos);
  EXPECT_NE(message("foo(1)").find("unknown function 'foo'"), std::string::npos);
}

// A hostile formula nested far past anything a person writes is refused with a located error, not a
// stack overflow; the error quotes the start of a long formula, not all of it.
TEST(Expression, DeepNestingIsRefusedBeforeTheStackOverflows) {
  const ParameterValues p;
  auto message = [&](const std::string& text) { return test::error_message([&] { evaluate_expression(text, p); }); };
  const auto nested = [](int depth, const std::string& open, const std::string& close) {
    std::string text;
    for (int level = 0; level < depth; ++level) text += open;
    text += "1";
    for (int level = 0; level < depth; ++level) text += close;
    return text;
  };
  for (const auto& [open, close] : std::vector<std::pair<std::string, std::string>>{
           {"(", ")"}, {"-", ""}, {"2^", ""}, {"sin(", ")"}, {"max(1,", ")"}}) {
    SCOPED_TRACE(open);
    const std::string hostile = message(nested(30000, open, close));
    EXPECT_NE(hostile.find("nested more than 256 levels deep"), std::string::npos) << hostile;
    EXPECT_LT(hostile.size(), 400u) << "the error quotes the whole formula";
    EXPECT_NE(hostile.find("characters)"), std::string::npos);
    EXPECT_EQ(message(nested(100, open, close)), "(no error)");
  }
  EXPECT_DOUBLE_EQ(evaluate_expression(nested(200, "(", ")"), p), 1.0);
}

}  // namespace
}  // namespace romp::scene
