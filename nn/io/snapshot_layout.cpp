// Field names, header checks, the paths beside a snapshot, and the plane/row transposition.
#include "nn/io/snapshot_layout.h"

#include <filesystem>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "kernels/core/error.h"

namespace romp::io {

FieldMask parse_fields(const std::vector<std::string>& names) {
  FieldMask fields = kFieldX;
  for (const std::string& name : names) {
    bool known = false;
    for (const FieldInfo& info : kFieldInfos) {
      if (name == info.name) {
        fields |= info.bit;
        known = true;
      }
    }
    if (!known)
      throw Error(
          fmt::format("unknown snapshot field \"{}\" (allowed: {})", name, fmt::join(field_names(kAllFields), ", ")));
  }
  return fields;
}

std::vector<std::uint64_t> field_shape(const FieldInfo& info, std::uint64_t n) {
  if (info.components == 1) return {n};
  if (info.components == 3) return {n, 3};
  return {n, 3, 3};
}

std::vector<std::string> field_names(FieldMask fields) {
  std::vector<std::string> names;
  for (const FieldInfo& info : kFieldInfos) {
    if (fields & info.bit) names.emplace_back(info.name);
  }
  return names;
}

std::vector<float>& FrameData::field(FieldMask bit) {
  return const_cast<std::vector<float>&>(static_cast<const FrameData&>(*this).field(bit));
}

const std::vector<float>& FrameData::field(FieldMask bit) const {
  switch (bit) {
    case kFieldX: return x;
    case kFieldV: return v;
    case kFieldF: return F;
    case kFieldC: return C;
    case kFieldStress: return stress;
    case kFieldJ: return J;
    case kFieldVonMises: return von_mises;
    case kFieldEnergyDensity: return energy_density;
    case kFieldJp: return Jp;
    case kFieldPlasticStrain: return plastic_strain;
    default: throw Error(fmt::format("FrameData::field: {} is not a single field bit", bit));
  }
}

void SnapshotHeader::validate() const {
  const std::size_t n = mass.size();
  if (X.size() != 3 * n || volume0.size() != n || material.size() != n || (!group.empty() && group.size() != n)) {
    throw Error(
        fmt::format("snapshot header: {} masses but {} reference-position values (3 planes), {} volumes and "
                    "{} material ids ({} group ids)",
                    n, X.size(), volume0.size(), material.size(), group.size()));
  }
  if (parameter_names.size() != parameter_values.size()) {
    throw Error(fmt::format("snapshot header: {} parameter names but {} values", parameter_names.size(),
                            parameter_values.size()));
  }
}

std::string frame_group_name(std::int64_t frame) { return fmt::format("/frames/{:06d}", frame); }

std::string partial_path(const std::string& snapshot_path) { return snapshot_path + ".partial"; }

std::string checkpoint_path(const std::string& snapshot_path) { return snapshot_path + ".checkpoint"; }

std::string xdmf_path(const std::string& snapshot_path) {
  return std::filesystem::path(snapshot_path).replace_extension(".xdmf").string();
}

std::string ply_frame_path(const std::string& snapshot_path, std::int64_t frame) {
  const std::filesystem::path path(snapshot_path);
  const std::filesystem::path folder = path.parent_path() / (path.stem().string() + "_ply");
  return (folder / fmt::format("frame_{:06d}.ply", frame)).string();
}

std::vector<float> planes_to_rows(const std::vector<float>& planes, int components) {
  const std::size_t n = planes.size() / std::size_t(components);
  std::vector<float> rows(planes.size());
  for (std::size_t c = 0; c < std::size_t(components); ++c) {
    for (std::size_t p = 0; p < n; ++p) rows[p * components + c] = planes[c * n + p];
  }
  return rows;
}

std::vector<float> rows_to_planes(const std::vector<float>& rows, int components) {
  const std::size_t n = rows.size() / std::size_t(components);
  std::vector<float> planes(rows.size());
  for (std::size_t c = 0; c < std::size_t(components); ++c) {
    for (std::size_t p = 0; p < n; ++p) planes[c * n + p] = rows[p * components + c];
  }
  return planes;
}

}  // namespace romp::io
