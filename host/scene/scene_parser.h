// Reads scene files (TOML, schema in scenes/README.md) into a resolved Scene.
#pragma once

#include <map>
#include <string>

#include "host/scene/expression.h"
#include "host/scene/scene.h"

namespace romp::scene {

// Materials to replace by learned laws: material name → law file (romp learn-law's output).
using LearnedLaws = std::map<std::string, std::string>;

// Parses `text` (named `file` in messages; relative mesh paths resolve against the file's folder).
// `overrides` replace declared [parameters] (a sweep member's values); an undeclared one is an error.
// Each of `laws` replaces its material's table by `neural = <the law's absolute path>` (keeping the
// density), as if the scene said so: the same scene runs with its analytic materials or with laws
// learned from them, and the resolved scene records which. A name the scene lacks is an error.
// Every problem throws romp::Error "file:line:column: key: why (allowed range)".
Scene parse_scene(const std::string& text, const std::string& file, const ParameterValues& overrides = {},
                  const LearnedLaws& laws = {});
Scene load_scene(const std::string& path, const ParameterValues& overrides = {}, const LearnedLaws& laws = {});

}  // namespace romp::scene
