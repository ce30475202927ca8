// PLY reader (ascii and binary_little_endian): vertex properties and face index lists.
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "host/geometry/mesh_io.h"
#include "host/geometry/parse_number.h"
#include "kernels/core/error.h"

namespace romp::geometry {
namespace {

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::Float32;  // of the items, for a list
  bool is_list = false;
  PlyType count_type = PlyType::UInt8;
};

struct PlyElement {
  std::string name;
  std::int64_t count = 0;
  std::vector<PlyProperty> properties;
};

bool parse_type(std::string_view word, PlyType& type) {
  static constexpr std::pair<std::string_view, PlyType> kNames[] = {
      {"char", PlyType::Int8},      {"int8", PlyType::Int8},       {"uchar", PlyType::UInt8},
      {"uint8", PlyType::UInt8},    {"short", PlyType::Int16},     {"int16", PlyType::Int16},
      {"ushort", PlyType::UInt16},  {"uint16", PlyType::UInt16},   {"int", PlyType::Int32},
      {"int32", PlyType::Int32},    {"uint", PlyType::UInt32},     {"uint32", PlyType::UInt32},
      {"float", PlyType::Float32},  {"float32", PlyType::Float32}, {"double", PlyType::Float64},
      {"float64", PlyType::Float64}};
  for (const auto& [type_name, value] : kNames)
    if (word == type_name) {
      type = value;
      return true;
    }
  return false;
}

bool is_integer(PlyType type) { return type != PlyType::Float32 && type != PlyType::Float64; }

int size_of(PlyType type) {
  switch (type) {
    case PlyType::Int8:
    case PlyType::UInt8: return 1;
    case PlyType::Int16:
    case PlyType::UInt16: return 2;
    case PlyType::Int32:
    case PlyType::UInt32:
    case PlyType::Float32: return 4;
    case PlyType::Float64: return 8;
  }
  return 0;
}

std::vector<std::string_view> words_of(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t at = 0;
  while ((at = line.find_first_not_of(" \t\r", at)) != std::string_view::npos) {
    const std::size_t end = std::min(line.find_first_of(" \t\r", at), line.size());
    words.push_back(line.substr(at, end - at));
    at = end;
  }
  return words;
}

// Reads the values of the body one at a time, as text tokens or little-endian bytes, and says
// where it is for messages: the line in ascii files, the element and item in binary ones.
class BodyCursor {
 public:
  BodyCursor(std::string_view body, bool binary, std::size_t first_line, const std::string& file)
      : body_(body), binary_(binary), line_(first_line), file_(file) {}

  void enter(const std::string& element, std::int64_t item) {
    element_ = &element;
    item_ = item;
  }

  [[noreturn]] void fail(const std::string& why) const {
    if (binary_) throw Error(fmt::format("{}: element '{}' item {}: {}", file_, *element_, item_, why));
    throw Error(fmt::format("{}:{}: {}", file_, line_, why));
  }

  double next(PlyType type) { return binary_ ? next_binary(type) : next_text(type); }

 private:
  double next_text(PlyType type) {
    while (at_ < body_.size() && std::strchr(" \t\r\n", body_[at_]) != nullptr)
      if (body_[at_++] == '\n') ++line_;
    if (at_ >= body_.size()) fail(fmt::format("the file ends inside element '{}' item {}", *element_, item_));
    const std::size_t start = at_;
    while (at_ < body_.size() && std::strchr(" \t\r\n", body_[at_]) == nullptr) ++at_;
    const std::string_view token = body_.substr(start, at_ - start);
    if (is_integer(type)) {
      std::int64_t value = 0;
      if (!parse_integer(token, value)) fail(fmt::format("bad integer '{}'", token));
      return double(value);
    }
    double value = 0.0;
    if (!parse_double(token, value)) fail(fmt::format("bad number '{}'", token));
    return value;
  }

  double next_binary(PlyType type) {
    const int size = size_of(type);
    if (body_.size() - at_ < std::size_t(size)) fail("the file is truncated");
    // Assembled byte by byte, so the reader does not depend on the host's byte order.
    std::uint64_t word = 0;
    for (int k = 0; k < size; ++k) word |= std::uint64_t(static_cast<unsigned char>(body_[at_ + k])) << (8 * k);
    at_ += std::size_t(size);
    switch (type) {
      case PlyType::Int8: return double(std::int8_t(word));
      case PlyType::UInt8: return double(std::uint8_t(word));
      case PlyType::Int16: return double(std::int16_t(word));
      case PlyType::UInt16: return double(std::uint16_t(word));
      case PlyType::Int32: return double(std::int32_t(word));
      case PlyType::UInt32: return double(std::uint32_t(word));
      case PlyType::Float32: {
        const std::uint32_t bits = std::uint32_t(word);
        float value;
        std::memcpy(&value, &bits, sizeof value);
        return double(value);
      }
      case PlyType::Float64: {
        double value;
        std::memcpy(&value, &word, sizeof value);
        return value;
      }
    }
    return 0.0;
  }

  std::string_view body_;
  bool binary_;
  std::size_t at_ = 0;
  std::size_t line_;
  const std::string& file_;
  const std::string* element_ = nullptr;
  std::int64_t item_ = 0;
};

// What romp reads of a PLY file: columns of the vertex element's scalar properties by name (empty
// where the file has no such property; x, y and z are required) and, when asked for, the faces as
// triangles (fan-triangulated).
struct PlyContent {
  std::int64_t vertex_count = 0;
  std::vector<std::vector<double>> columns;
  std::vector<std::array<std::int32_t, 3>> triangles;
};

PlyContent read_ply(const std::string& bytes, const std::string& name, const std::vector<std::string>& column_names,
                    bool with_faces) {
  // Header: text lines up to end_header.
  std::vector<PlyElement> elements;
  bool binary = false, ended = false;
  std::size_t at = 0, line_number = 0;
  while (!ended) {
    if (at >= bytes.size()) throw Error(fmt::format("{}: the PLY header has no end_header line", name));
    const std::size_t end = std::min(bytes.find('\n', at), bytes.size());
    const std::vector<std::string_view> words = words_of(std::string_view(bytes).substr(at, end - at));
    at = end + 1;
    ++line_number;
    const auto fail = [&](const std::string& why) { throw Error(fmt::format("{}:{}: {}", name, line_number, why)); };
    if (line_number == 1) {
      if (words.size() != 1 || words[0] != "ply") fail("not a PLY file: the first line must be 'ply'");
      continue;
    }
    if (words.empty() || words[0] == "comment" || words[0] == "obj_info") continue;
    if (words[0] == "format") {
      if (words.size() < 2 || (words[1] != "ascii" && words[1] != "binary_little_endian"))
        fail(fmt::format("unsupported PLY format '{}' (romp reads ascii and binary_little_endian)",
                         words.size() < 2 ? "" : words[1]));
      binary = words[1] == "binary_little_endian";
    } else if (words[0] == "element") {
      std::int64_t count = 0;
      if (words.size() != 3 || !parse_integer(words[2], count) || count < 0)
        fail("expected 'element <name> <count>' with a count >= 0");
      elements.push_back({std::string(words[1]), count, {}});
    } else if (words[0] == "property") {
      if (elements.empty()) fail("a property before any element");
      PlyProperty property;
      if (words.size() == 5 && words[1] == "list") {
        property.is_list = true;
        if (!parse_type(words[2], property.count_type) || !parse_type(words[3], property.type))
          fail(fmt::format("unknown list types '{} {}'", words[2], words[3]));
        if (!is_integer(property.count_type)) fail("a list's count type must be an integer type");
        property.name = std::string(words[4]);
      } else if (words.size() == 3) {
        if (!parse_type(words[1], property.type)) fail(fmt::format("unknown property type '{}'", words[1]));
        property.name = std::string(words[2]);
      } else {
        fail("expected 'property <type> <name>' or 'property list <count type> <item type> <name>'");
      }
      elements.back().properties.push_back(property);
    } else if (words[0] == "end_header") {
      ended = true;
    } else {
      fail(fmt::format("unknown header keyword '{}'", words[0]));
    }
  }

  // Which properties hold what romp needs.
  const auto find = [&](const char* element_name) {
    return std::find_if(elements.begin(), elements.end(), [&](const PlyElement& e) { return e.name == element_name; });
  };
  const auto vertex_element = find("vertex");
  const auto face_element = find("face");
  if (vertex_element == elements.end())
    throw Error(fmt::format("{}: the PLY header declares no 'vertex' element", name));
  if (with_faces && (face_element == elements.end() || face_element->count == 0))
    throw Error(fmt::format("{}: no faces", name));
  // column_of[k]: the column vertex property k fills, or -1.
  std::vector<int> column_of(vertex_element->properties.size(), -1);
  std::vector<bool> found(column_names.size(), false);
  for (std::size_t k = 0; k < vertex_element->properties.size(); ++k)
    for (std::size_t c = 0; c < column_names.size(); ++c)
      if (vertex_element->properties[k].name == column_names[c] && !vertex_element->properties[k].is_list) {
        column_of[k] = int(c);
        found[c] = true;
      }
  for (int a = 0; a < 3; ++a)
    if (!found[std::size_t(a)])
      throw Error(fmt::format("{}: the vertex element has no property '{}'", name, column_names[std::size_t(a)]));
  int indices_property = -1;
  for (std::size_t k = 0; with_faces && k < face_element->properties.size(); ++k) {
    const PlyProperty& p = face_element->properties[k];
    if (p.is_list && is_integer(p.type) && (p.name == "vertex_indices" || p.name == "vertex_index"))
      indices_property = int(k);
  }
  if (with_faces && indices_property < 0)
    throw Error(fmt::format("{}: the face element has no integer list 'vertex_indices' (or 'vertex_index')", name));

  // Body: every element in order, keeping the vertex columns and face indices.
  PlyContent content;
  const std::int64_t vertex_count = vertex_element->count;
  content.vertex_count = vertex_count;
  content.columns.resize(column_names.size());
  for (std::size_t c = 0; c < column_names.size(); ++c)
    if (found[c])
      // Every value takes at least one byte, which bounds what a corrupt count can make us reserve.
      content.columns[c].reserve(std::size_t(std::min<std::int64_t>(vertex_count, std::int64_t(bytes.size()))));
  BodyCursor cursor(std::string_view(bytes).substr(std::min(at, bytes.size())), binary, line_number + 1, name);
  std::vector<std::int32_t> polygon;
  for (const PlyElement& element : elements) {
    const bool is_vertex = &element == &*vertex_element;
    const bool is_face = with_faces && &element == &*face_element;
    for (std::int64_t item = 0; item < element.count; ++item) {
      cursor.enter(element.name, item);
      polygon.clear();
      for (std::size_t k = 0; k < element.properties.size(); ++k) {
        const PlyProperty& property = element.properties[k];
        if (!property.is_list) {
          const double value = cursor.next(property.type);
          if (is_vertex && column_of[k] >= 0) content.columns[std::size_t(column_of[k])].push_back(value);
          continue;
        }
        const double count = cursor.next(property.count_type);
        if (count < 0) cursor.fail(fmt::format("negative list length {}", count));
        const bool keep = is_face && int(k) == indices_property;
        for (std::int64_t i = 0; i < std::int64_t(count); ++i) {
          const double value = cursor.next(property.type);
          if (!keep) continue;
          if (value < 0 || value >= double(vertex_count))
            cursor.fail(fmt::format("vertex index {} out of range: the file has {} vertices", value, vertex_count));
          polygon.push_back(std::int32_t(value));
        }
        if (keep && polygon.size() < 3) cursor.fail(fmt::format("a face with {} vertices", polygon.size()));
      }
      for (std::size_t k = 1; k + 1 < polygon.size(); ++k)
        content.triangles.push_back({polygon[0], polygon[k], polygon[k + 1]});
    }
  }
  return content;
}

}  // namespace

TriangleMesh parse_ply(const std::string& bytes, const std::string& name) {
  const PlyContent content = read_ply(bytes, name, {"x", "y", "z"}, /*with_faces=*/true);
  TriangleMesh mesh;
  mesh.name = name;
  mesh.vertices.reserve(std::size_t(content.vertex_count));
  for (std::int64_t i = 0; i < content.vertex_count; ++i)
    mesh.vertices.push_back(Vec3<double>(content.columns[0][std::size_t(i)], content.columns[1][std::size_t(i)],
                                         content.columns[2][std::size_t(i)]));
  mesh.triangles = content.triangles;
  return mesh;
}

PointCloud parse_ply_points(const std::string& bytes, const std::string& name) {
  const PlyContent content = read_ply(bytes, name, {"x", "y", "z", "vx", "vy", "vz", "volume"}, /*with_faces=*/false);
  PointCloud cloud;
  const bool velocity = !content.columns[3].empty() && !content.columns[4].empty() && !content.columns[5].empty();
  const bool volume = !content.columns[6].empty();
  for (std::int64_t i = 0; i < content.vertex_count; ++i) {
    const std::size_t k = std::size_t(i);
    cloud.x.push_back(Vec3<double>(content.columns[0][k], content.columns[1][k], content.columns[2][k]));
    if (velocity) cloud.v.push_back(Vec3<double>(content.columns[3][k], content.columns[4][k], content.columns[5][k]));
    if (volume) cloud.volume.push_back(content.columns[6][k]);
  }
  return cloud;
}

}  // namespace romp::geometry
