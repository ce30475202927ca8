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
  // Checked by kind before any value is read: value() and get() throw the JSON library's type_error for a
  // value of another kind (train-rom then exited 4, as if the machine had failed), and get<std::int64_t>()
  // of a float beyond int64's range is undefined behaviour.
  if (!manifest.is_object())
    throw io::UnusableFileError(label + ": manifest.json: a JSON " + manifest.type_name() + ", not an object");
  const auto format = manifest.find("format");
  if (format == manifest.end() || !format->is_string() || format->get<std::string>() != kSweepFormat)
    throw io::UnusableFileError(label + ": manifest.json: format is not \"" + kSweepFormat + "\"");
  const auto version = manifest.find("format_version");
  // A number is shown, anything else named by its kind: printing a hostile value (an array nested 200,000
  // deep) recurses as deep as it is nested.
  const std::string shown = version == manifest.end() ? "missing"
                            : version->is_number()    ? version->dump()
                                                      : std::string("(a JSON ") + version->type_name() + ")";
  if (version == manifest.end() || !version->is_number_integer() || version->get<std::int64_t>() < 1 ||
      version->get<std::int64_t>() > kSweepFormatVersion) {
    throw io::UnusableFileError(label + ": manifest.json: format_version " + shown +
                                " is not one this romp reads (1 .. " + std::to_string(kSweepFormatVersion) + ")");
  }
  return manifest;
}

SweepMember parse_member(const nlohmann::json& entry, const std::vector<std::string>& names) {
  SweepMember member;
  // An integer: a float there (1e300) would convert with undefined behaviour.
  if (!entry.at("index").is_number_integer()) throw io::UnusableFileError("index is not an integer");
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
