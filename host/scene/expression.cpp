// A recursive-descent compiler of scene-file formulas to postfix operations, and their evaluation.
#include "host/scene/expression.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <utility>
#include <vector>

#include "kernels/core/error.h"

namespace romp::scene {
namespace {

constexpr double kPi = 3.14159265358979323846;
// How deeply a formula may nest (parentheses, calls, unary signs and powers together). Each level is a
// few frames of the evaluator's recursion; the limit keeps a hostile formula from overflowing the stack,
// and no formula a person writes comes near it.
constexpr int kMaxNesting = 256;
// How much of a long formula an error message quotes.
constexpr std::size_t kQuotedLength = 80;

using Operation = Formula::Operation;
using Kind = Operation::Kind;

using UnaryFunction = double (*)(double);
constexpr std::pair<const char*, UnaryFunction> kUnary[] = {
    {"sin", [](double a) { return std::sin(a); }},         {"cos", [](double a) { return std::cos(a); }},
    {"tan", [](double a) { return std::tan(a); }},         {"asin", [](double a) { return std::asin(a); }},
    {"acos", [](double a) { return std::acos(a); }},       {"atan", [](double a) { return std::atan(a); }},
    {"sqrt", [](double a) { return std::sqrt(a); }},       {"exp", [](double a) { return std::exp(a); }},
    {"log", [](double a) { return std::log(a); }},         {"abs", [](double a) { return std::fabs(a); }},
    {"radians", [](double a) { return a * kPi / 180.0; }}, {"degrees", [](double a) { return a * 180.0 / kPi; }},
};
using BinaryFunction = double (*)(double, double);
constexpr std::pair<const char*, BinaryFunction> kBinary[] = {
    {"atan2", [](double a, double b) { return std::atan2(a, b); }},
    {"min", [](double a, double b) { return std::min(a, b); }},
    {"max", [](double a, double b) { return std::max(a, b); }},
    {"pow", [](double a, double b) { return std::pow(a, b); }},
};

// Compiles a formula into postfix operations, in the order the grammar below reads it.
class Parser {
 public:
  Parser(const std::string& text, const ParameterValues& parameters, const std::vector<std::string>& variables)
      : text_(text), parameters_(parameters), variables_(variables) {}

  std::vector<Operation> parse() {
    sum();
    skip_space();
    if (at_ < text_.size()) fail(fmt::format("unexpected '{}'", text_[at_]));
    return std::move(program_);
  }

 private:
  // sum := product (('+' | '-') product)*
  void sum() {
    product();
    for (;;) {
      if (accept('+'))
        operand_then(&Parser::product, Kind::Add);
      else if (accept('-'))
        operand_then(&Parser::product, Kind::Subtract);
      else
        return;
    }
  }

  // product := unary (('*' | '/') unary)*
  void product() {
    unary();
    for (;;) {
      if (accept('*'))
        operand_then(&Parser::unary, Kind::Multiply);
      else if (accept('/'))
        operand_then(&Parser::unary, Kind::Divide);
      else
        return;
    }
  }

  // The right operand, then the operation.
  void operand_then(void (Parser::*operand)(), Kind kind) {
    (this->*operand)();
    emit({kind});
  }

  // unary := ('-' | '+') unary | power; so -2^2 = -4 as in mathematics. Every path by which the grammar
  // recurses passes here (a parenthesis or a call through sum, a sign, a power's exponent), so this is
  // where the nesting is counted.
  void unary() {
    const Nesting level(*this);
    if (accept('-')) return operand_then(&Parser::unary, Kind::Negate);
    if (accept('+')) return unary();
    power();
  }

  // power := primary ('^' unary)?
  void power() {
    primary();
    if (accept('^')) operand_then(&Parser::unary, Kind::Power);
  }

  void primary() {
    skip_space();
    if (accept('(')) {
      sum();
      expect(')');
      return;
    }
    if (at_ < text_.size() && (std::isdigit(static_cast<unsigned char>(text_[at_])) || text_[at_] == '.'))
      return number();
    if (at_ < text_.size() && (std::isalpha(static_cast<unsigned char>(text_[at_])) || text_[at_] == '_')) {
      const std::size_t start = at_;
      while (at_ < text_.size() && (std::isalnum(static_cast<unsigned char>(text_[at_])) || text_[at_] == '_')) ++at_;
      const std::string name = text_.substr(start, at_ - start);
      if (accept('(')) return call(name, start);
      return variable(name, start);
    }
    if (at_ >= text_.size()) fail("the formula ends where a value is expected");
    fail(fmt::format("unexpected '{}' where a value is expected", text_[at_]));
  }

  void number() {
    const char* begin = text_.c_str() + at_;
    char* end = nullptr;
    const double value = std::strtod(begin, &end);
    if (end == begin) fail("malformed number");
    at_ += std::size_t(end - begin);
    emit({Kind::Constant, value});
  }

  void variable(const std::string& name, std::size_t column) {
    for (std::size_t slot = 0; slot < variables_.size(); ++slot)
      if (variables_[slot] == name) return emit({Kind::Variable, 0.0, int(slot)});
    if (name == "pi") return emit({Kind::Constant, kPi});
    const auto found = parameters_.find(name);
    if (found != parameters_.end()) return emit({Kind::Constant, found->second});
    std::string known;
    for (const auto& [parameter, value] : parameters_) known += (known.empty() ? "" : ", ") + parameter;
    at_ = column;
    fail(fmt::format("unknown name '{}' (parameters: {}{})", name, known.empty() ? "none declared" : known,
                     variables_.empty() ? "" : fmt::format("; variables: {}", fmt::join(variables_, ", "))));
  }

  void call(const std::string& name, std::size_t column) {
    std::size_t arguments = 1;
    sum();
    while (accept(',')) {
      sum();
      ++arguments;
    }
    expect(')');
    auto arity = [&](std::size_t n) {
      if (arguments != n) {
        at_ = column;
        fail(fmt::format("{}() takes {} argument{}, got {}", name, n, n == 1 ? "" : "s", arguments));
      }
    };
    for (std::size_t f = 0; f < std::size(kUnary); ++f) {
      if (name != kUnary[f].first) continue;
      arity(1);
      return emit({Kind::Unary, 0.0, int(f)});
    }
    for (std::size_t f = 0; f < std::size(kBinary); ++f) {
      if (name != kBinary[f].first) continue;
      arity(2);
      return emit({Kind::Binary, 0.0, int(f)});
    }
    at_ = column;
    fail(fmt::format("unknown function '{}'", name));
  }

  void emit(const Operation& operation) { program_.push_back(operation); }

  void skip_space() {
    while (at_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[at_]))) ++at_;
  }
  bool accept(char c) {
    skip_space();
    if (at_ < text_.size() && text_[at_] == c) {
      ++at_;
      return true;
    }
    return false;
  }
  void expect(char c) {
    if (!accept(c)) fail(fmt::format("expected '{}'", c));
  }
  [[noreturn]] void fail(const std::string& why) const {
    const std::string quoted =
        text_.size() <= kQuotedLength
            ? fmt::format("\"{}\"", text_)
            : fmt::format("\"{}...\" ({} characters)", text_.substr(0, kQuotedLength), text_.size());
    throw Error(fmt::format("formula {}, column {}: {}", quoted, at_ + 1, why));
  }

  // One level of nesting for the scope of a unary(), refused past kMaxNesting.
  class Nesting {
   public:
    explicit Nesting(Parser& parser) : parser_(parser) {
      if (++parser_.depth_ > kMaxNesting)
        parser_.fail(
            fmt::format("nested more than {} levels deep (parentheses, calls, signs and powers)", kMaxNesting));
    }
    ~Nesting() { --parser_.depth_; }
    Nesting(const Nesting&) = delete;
    Nesting& operator=(const Nesting&) = delete;

   private:
    Parser& parser_;
  };

  const std::string& text_;
  const ParameterValues& parameters_;
  const std::vector<std::string>& variables_;
  std::vector<Operation> program_;
  std::size_t at_ = 0;
  int depth_ = 0;
};

}  // namespace

Formula::Formula(const std::string& text, const ParameterValues& parameters, const std::vector<std::string>& variables)
    : program_(Parser(text, parameters, variables).parse()) {
  for (const Operation& operation : program_) uses_variables_ |= operation.kind == Kind::Variable;
}

double Formula::operator()(const std::vector<double>& variables) const {
  // The stack never holds more values than the program has operations; a formula is short.
  std::vector<double> stack;
  stack.reserve(program_.size());
  auto pop = [&stack] {
    const double value = stack.back();
    stack.pop_back();
    return value;
  };
  for (const Operation& operation : program_) {
    switch (operation.kind) {
      case Kind::Constant: stack.push_back(operation.constant); continue;
      case Kind::Variable: stack.push_back(variables.at(std::size_t(operation.index))); continue;
      case Kind::Negate: stack.back() = -stack.back(); continue;
      case Kind::Unary: stack.back() = kUnary[operation.index].second(stack.back()); continue;
      default: break;
    }
    const double right = pop();
    double& left = stack.back();
    switch (operation.kind) {
      case Kind::Add: left += right; break;
      case Kind::Subtract: left -= right; break;
      case Kind::Multiply: left *= right; break;
      case Kind::Divide: left /= right; break;
      case Kind::Power: left = std::pow(left, right); break;
      case Kind::Binary: left = kBinary[operation.index].second(left, right); break;
      default: break;
    }
  }
  return stack.back();
}

double evaluate_expression(const std::string& text, const ParameterValues& parameters) {
  return Formula(text, parameters)({});
}

ParameterValues parse_assignments(const std::vector<std::string>& assignments) {
  ParameterValues values;
  for (const std::string& assignment : assignments) {
    const std::size_t equals = assignment.find('=');
    if (equals == std::string::npos || equals == 0)
      throw Error(fmt::format("expected name=value, got '{}'", assignment));
    values[assignment.substr(0, equals)] = evaluate_expression(assignment.substr(equals + 1), {});
  }
  return values;
}

}  // namespace romp::scene
