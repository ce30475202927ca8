// DIR/manifest.json of a sweep folder: format, version, parameters and members (sweep_manifest.h).
#include "nn/rom/sweep_manifest.h"

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "kernels/core/error.h"
#include "nn/io/unusable_file_error.h"

namespace romp::nn::rom {
namespace {

namespace fs = std::filesystem;

constexpr const char* kSweepFormat = "romp-sweep";
constexpr std::int64_t kSweepFormatVersion = 1;

nlohmann::json read_manifest(const std::string& label, const fs::path& path) {
  std::ifstream in(path);
  if (!in)
    throw io::UnusableFileError(label + ": no " + path.filename().string() +
                                " (a folder written by romp sweep holds one)");
  nlohmann::json manifest;
  try {
    in >> manifest;
  } catch (const nlohmann::json::exception& error) {
    throw io::UnusableFileError(label + ": " + path.filename().string() + ": not valid JSON: " + error.what());
  }
  if (manifest.value("format", std::string()) != kSweepFormat)
    throw io::UnusableFileError(label + ": manifest.json: format is not \"" + kSweepFormat + "\"");
  const std::int64_t version = manifest.value("format_version", std::int64_t(0));
  if (version < 1 || version > kSweepFormatVersion) {
    throw io::UnusableFileError(label + ": manifest.json: format_version " + std::to_string(version) +
                                " is not one this romp reads (1 .. " + std::to_string(kSweepFormatVersion) + ")");
  }
  return manifest;
}

SweepMember parse_member(const nlohmann::json& entry, const std::vector<std::string>& names) {
  SweepMember member;
  member.index = entry.at("index").get<std::int64_t>();
  for (const std::string& name : names) member.values.push_back(entry.at("values").at(name).get<double>());
  const std::string split = entry.at("split").get<std::string>();
  if (split != "train" && split != "test")
    throw io::UnusableFileError("split is \"" + split + "\", expected \"train\" or \"test\"");
  member.test = split == "test";
  member.snapshot = entry.at("snapshot").get<std::string>();
  return member;
}

}  // namespace

bool SweepMember::operator==(const SweepMember& other) const {
  return index == other.index && values == other.values && test == other.test && snapshot == other.snapshot;
}

SweepManifest read_sweep_manifest(const std::string& dir) {
  const std::string label = "sweep " + dir;
  const nlohmann::json manifest = read_manifest(label, fs::path(dir) / "manifest.json");
  SweepManifest result;
  try {
    result.parameter_names = manifest.at("parameters").get<std::vector<std::string>>();
    std::size_t position = 0;
    for (const nlohmann::json& entry : manifest.at("members")) {
      try {
        result.members.push_back(parse_member(entry, result.parameter_names));
      } catch (const std::exception& error) {
        // Named by its place in the list, not by its text: printing a hostile entry (an array nested
        // 200,000 deep) recurses as deep as it is nested and overflowed the stack.
        throw Error("members[" + std::to_string(position) + "] (a JSON " + entry.type_name() + "): " + error.what());
      }
      ++position;
    }
  } catch (const std::exception& error) {
    throw io::UnusableFileError(label + ": manifest.json: " + error.what());
  }
  if (result.members.empty()) throw io::UnusableFileError(label + ": manifest.json lists no members");
  return result;
}

}  // namespace romp::nn::rom
