// Arithmetic expressions in scene files: a number may be written as a formula over the scene's named
// parameters ("speed * cos(angle)"), so a sweep can vary one parameter that drives several values.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace romp::scene {

using ParameterValues = std::map<std::string, double>;

// Evaluates `text`: numbers, parameter names, pi, + - * / ^ (right-associative), unary minus,
// parentheses and the functions sin cos tan asin acos atan atan2 sqrt exp log abs min max pow
// radians degrees. Throws romp::Error naming the column and the offending token, or the unknown name
// and the parameters that exist.
double evaluate_expression(const std::string& text, const ParameterValues& parameters);

// "name=value" assignments (the command line's --set), each value an expression without parameters.
// Throws romp::Error naming the assignment that is not of that form.
ParameterValues parse_assignments(const std::vector<std::string>& assignments);

}  // namespace romp::scene
