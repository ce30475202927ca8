// The manifest of a sweep folder (DIR/manifest.json, format "romp-sweep", written by `romp sweep`): the swept
// parameters and the members with their split, read without LibTorch (train-rom reads it through
// load_rom_dataset; tests/fuzz/manifest_fuzzer.cpp reads it alone).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace romp::nn::rom {

// One member of the sweep (a parameter instance μ), as DIR/manifest.json lists it.
struct SweepMember {
  std::int64_t index = 0;
  std::vector<double> values;  // μ, in the sweep's parameter order
  bool test = false;           // held out from training
  std::string snapshot;        // file name in the sweep folder, e.g. "member_000003.h5"

  bool operator==(const SweepMember& other) const;
};

struct SweepManifest {
  std::vector<std::string> parameter_names;
  std::vector<SweepMember> members;  // manifest order, at least one
};

// Reads DIR/manifest.json. Throws io::UnusableFileError naming the folder when it is missing, not JSON, of
// another format or version, lists no members, or a member lacks a field or has one of the wrong kind
// (named by its place in the list, "members[3]").
SweepManifest read_sweep_manifest(const std::string& dir);

}  // namespace romp::nn::rom
