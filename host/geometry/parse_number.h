// Locale-independent parsing of one whole text token as a number, for the mesh readers.
#pragma once

#include <charconv>
#include <cmath>
#include <cstdint>
#include <string_view>

namespace romp::geometry {

// True when all of `token` is a finite decimal number (an optional leading '+' allowed).
inline bool parse_double(std::string_view token, double& value) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
  const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
  return error == std::errc() && end == token.data() + token.size() && !token.empty() && std::isfinite(value);
}

// True when all of `token` is a decimal integer that fits in 64 bits.
inline bool parse_integer(std::string_view token, std::int64_t& value) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
  const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
  return error == std::errc() && end == token.data() + token.size() && !token.empty();
}

}  // namespace romp::geometry
