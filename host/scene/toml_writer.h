// Prints a TOML table the way scene files are written: shortest round-trip numbers, simple keys
// before sub-tables, and top-level tables in the schema's order, so `romp check` output reads like
// the scene it resolves.
#pragma once

#include <string>
#include <vector>

#include <toml++/toml.h>

namespace romp::scene {

// `top_order` lists top-level keys to print first, in that order; the rest follow alphabetically.
std::string to_toml(const toml::table& table, const std::vector<std::string>& top_order);

}  // namespace romp::scene
