// A recursive-descent evaluator for scene-file formulas (no allocation beyond the error text).
#include "host/scene/expression.h"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
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

class Parser {
 public:
  Parser(const std::string& text, const ParameterValues& parameters) : text_(text), parameters_(parameters) {}

  double parse() {
    const double value = sum();
    skip_space();
    if (at_ < text_.size()) fail(fmt::format("unexpected '{}'", text_[at_]));
    return value;
  }

 private:
  // sum := product (('+' | '-') product)*
  double sum() {
    double value = product();
    for (;;) {
      if (accept('+'))
        value += product();
      else if (accept('-'))
        value -= product();
      else
        return value;
    }
  }

  // product := unary (('*' | '/') unary)*
  double product() {
    double value = unary();
    for (;;) {
      if (accept('*'))
        value *= unary();
      else if (accept('/'))
        value /= unary();
      else
        return value;
    }
  }

  // unary := ('-' | '+') unary | power; so -2^2 = -4 as in mathematics. Every path by which the grammar
  // recurses passes here (a parenthesis or a call through sum, a sign, a power's exponent), so this is
  // where the nesting is counted.
  double unary() {
    const Nesting level(*this);
    if (accept('-')) return -unary();
    if (accept('+')) return unary();
    return power();
  }

  // power := primary ('^' unary)?
  double power() {
    const double base = primary();
    return accept('^') ? std::pow(base, unary()) : base;
  }

  double primary() {
    skip_space();
    if (accept('(')) {
      const double value = sum();
      expect(')');
      return value;
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

  double number() {
    const char* begin = text_.c_str() + at_;
    char* end = nullptr;
    const double value = std::strtod(begin, &end);
    if (end == begin) fail("malformed number");
    at_ += std::size_t(end - begin);
    return value;
  }

  double variable(const std::string& name, std::size_t column) {
    if (name == "pi") return kPi;
    const auto found = parameters_.find(name);
    if (found != parameters_.end()) return found->second;
    std::string known;
    for (const auto& [parameter, value] : parameters_) known += (known.empty() ? "" : ", ") + parameter;
    at_ = column;
    fail(fmt::format("unknown name '{}' (parameters: {})", name, known.empty() ? "none declared" : known));
  }

  double call(const std::string& name, std::size_t column) {
    std::vector<double> args{sum()};
    while (accept(',')) args.push_back(sum());
    expect(')');
    auto arity = [&](std::size_t n) {
      if (args.size() != n) {
        at_ = column;
        fail(fmt::format("{}() takes {} argument{}, got {}", name, n, n == 1 ? "" : "s", args.size()));
      }
    };
    using Unary = double (*)(double);
    static const std::pair<const char*, Unary> kUnary[] = {
        {"sin", [](double a) { return std::sin(a); }},         {"cos", [](double a) { return std::cos(a); }},
        {"tan", [](double a) { return std::tan(a); }},         {"asin", [](double a) { return std::asin(a); }},
        {"acos", [](double a) { return std::acos(a); }},       {"atan", [](double a) { return std::atan(a); }},
        {"sqrt", [](double a) { return std::sqrt(a); }},       {"exp", [](double a) { return std::exp(a); }},
        {"log", [](double a) { return std::log(a); }},         {"abs", [](double a) { return std::fabs(a); }},
        {"radians", [](double a) { return a * kPi / 180.0; }}, {"degrees", [](double a) { return a * 180.0 / kPi; }},
    };
    for (const auto& [known, function] : kUnary) {
      if (name != known) continue;
      arity(1);
      return function(args[0]);
    }
    if (name == "atan2" || name == "min" || name == "max" || name == "pow") {
      arity(2);
      if (name == "atan2") return std::atan2(args[0], args[1]);
      if (name == "min") return std::min(args[0], args[1]);
      if (name == "max") return std::max(args[0], args[1]);
      return std::pow(args[0], args[1]);
    }
    at_ = column;
    fail(fmt::format("unknown function '{}'", name));
  }

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
  std::size_t at_ = 0;
  int depth_ = 0;
};

}  // namespace

double evaluate_expression(const std::string& text, const ParameterValues& parameters) {
  return Parser(text, parameters).parse();
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
