// Arithmetic expressions in scene files: a number may be written as a formula over the scene's named
// parameters ("speed * cos(angle)"), so a sweep can vary one parameter that drives several values, and
// some values (an object's initial velocity) as a formula of the position too ("omega * y").
#pragma once

#include <map>
#include <string>
#include <vector>

namespace romp::scene {

using ParameterValues = std::map<std::string, double>;

// A formula compiled once and evaluated at many values of its variables (e.g. x, y, z at every
// particle): numbers, parameter names, variable names, pi, + - * / ^ (right-associative), unary minus,
// parentheses and the functions sin cos tan asin acos atan atan2 sqrt exp log abs min max pow radians
// degrees. Parameters are fixed when it is compiled; a variable takes its value at each evaluation.
class Formula {
 public:
  // Throws romp::Error naming the column and the offending token, or the unknown name and the
  // parameters and variables that exist. A variable hides a parameter of the same name.
  Formula(const std::string& text, const ParameterValues& parameters, const std::vector<std::string>& variables = {});

  // The value at `variables` (one value per variable name, in the order they were given).
  double operator()(const std::vector<double>& variables) const;
  // Whether the value depends on a variable at all.
  bool uses_variables() const { return uses_variables_; }

  // One step of the compiled program, run on a value stack (postfix order).
  struct Operation {
    enum class Kind { Constant, Variable, Negate, Add, Subtract, Multiply, Divide, Power, Unary, Binary };
    Kind kind;
    double constant = 0.0;  // Constant
    int index = 0;          // Variable: its slot; Unary / Binary: the function's
  };

 private:
  std::vector<Operation> program_;
  bool uses_variables_ = false;
};

// Evaluates `text` (a formula without variables) with `parameters`.
double evaluate_expression(const std::string& text, const ParameterValues& parameters);

// "name=value" assignments (the command line's --set), each value an expression without parameters.
// Throws romp::Error naming the assignment that is not of that form.
ParameterValues parse_assignments(const std::vector<std::string>& assignments);

}  // namespace romp::scene
