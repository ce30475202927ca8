// Parameter sweeps: the [sweep] table of a scene (full factorial grid, uniform random or Latin
// hypercube over named parameters) and its members with a seeded or evenly spaced train/test split.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "host/scene/expression.h"
#include "host/scene/toml_reader.h"

namespace romp::scene {

enum class SweepMethod { Grid, Random, LatinHypercube };

struct SweepAxis {
  std::string parameter;
  std::vector<double> values;    // grid: the values taken
  double low = 0.0, high = 0.0;  // random, Latin hypercube: the interval sampled
};

struct SweepSpec {
  SweepMethod method = SweepMethod::Grid;
  std::int64_t samples = 0;  // random, Latin hypercube: the number of members
  std::uint64_t seed = 0;
  double test_fraction = 0.0;    // held out at random
  std::int64_t train_every = 0;  // > 0: the members whose index is a multiple train, the rest test
  std::vector<SweepAxis> axes;
};

struct SweepMember {
  std::int64_t index = 0;
  ParameterValues values;  // the swept parameters only
  bool test = false;       // held out of training
};

// Reads [sweep]; every swept name must be one of `declared` (the [parameters] table).
SweepSpec read_sweep(TableReader& sweep, const ParameterValues& declared);

// The members in a fixed order (grid: last axis fastest), identical on every machine for a seed
// (geometry::Random draws the same numbers everywhere).
std::vector<SweepMember> sweep_members(const SweepSpec& sweep);

}  // namespace romp::scene
