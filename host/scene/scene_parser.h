// Reads scene files (TOML, schema in scenes/README.md) into a resolved Scene.
#pragma once

#include <string>

#include "host/scene/expression.h"
#include "host/scene/scene.h"

namespace romp::scene {

// Parses `text` (named `file` in messages; relative mesh paths resolve against the file's folder).
// `overrides` replace declared [parameters] (a sweep member's values); an undeclared one is an error.
// Every problem throws romp::Error "file:line:column: key: why (allowed range)".
Scene parse_scene(const std::string& text, const std::string& file, const ParameterValues& overrides = {});
Scene load_scene(const std::string& path, const ParameterValues& overrides = {});

}  // namespace romp::scene
