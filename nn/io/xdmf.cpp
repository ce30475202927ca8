// XDMF sidecar text. Written for ParaView's Xdmf3 reader; the elements used (Polyvertex topology,
// XYZ geometry, HDF data items, Time) read the same in its older XDMF 2 reader.
#include "nn/io/xdmf.h"

#include <fmt/format.h>

#include "nn/io/atomic_file.h"

namespace romp::io {
namespace {

std::string escape_xml(const std::string& text) {
  std::string escaped;
  for (char c : text) {
    switch (c) {
      case '&': escaped += "&amp;"; break;
      case '<': escaped += "&lt;"; break;
      case '>': escaped += "&gt;"; break;
      case '"': escaped += "&quot;"; break;
      case '\'': escaped += "&apos;"; break;
      default: escaped += c;
    }
  }
  return escaped;
}

// One HDF5 data item; `dimensions` must match the dataset's shape, which the HDF5 controller selects.
std::string data_item(const std::string& file, const std::string& dataset, const std::string& dimensions,
                      const char* number_type, const std::string& indent) {
  return fmt::format(
      "{}<DataItem Dimensions=\"{}\" NumberType=\"{}\" Precision=\"4\" Format=\"HDF\">{}:{}</DataItem>\n", indent,
      dimensions, number_type, file, dataset);
}

std::string attribute(const std::string& name, const char* type, const std::string& file, const std::string& dataset,
                      const std::string& dimensions, const char* number_type) {
  return fmt::format("        <Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"Node\">\n", name, type) +
         data_item(file, dataset, dimensions, number_type, "          ") + "        </Attribute>\n";
}

}  // namespace

std::string xdmf_document(const XdmfSnapshot& snapshot) {
  const std::string file = escape_xml(snapshot.hdf5_file);
  const std::int64_t n = snapshot.particle_count;
  const std::string vector_dims = fmt::format("{} 3", n);
  const std::string tensor_dims = fmt::format("{} 3 3", n);
  const std::string scalar_dims = fmt::format("{}", n);

  // The per-particle constants are the same datasets in every frame.
  std::string constants;
  constants += attribute("X", "Vector", file, "/particles/X", vector_dims, "Float");
  constants += attribute("mass", "Scalar", file, "/particles/mass", scalar_dims, "Float");
  constants += attribute("volume0", "Scalar", file, "/particles/volume0", scalar_dims, "Float");
  constants += attribute("material", "Scalar", file, "/particles/material", scalar_dims, "Int");
  if (snapshot.has_group) constants += attribute("group", "Scalar", file, "/particles/group", scalar_dims, "Int");
  constants += attribute("id", "Scalar", file, "/particles/id", scalar_dims, "Int");

  std::string text = "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n";
  text += "<Xdmf Version=\"3.0\">\n  <Domain>\n";
  text += "    <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t k = 0; k < snapshot.frame_times.size(); ++k) {
    const std::string group = frame_group_name(std::int64_t(k));
    text += fmt::format("      <Grid Name=\"frame_{:06d}\" GridType=\"Uniform\">\n", k);
    text += fmt::format("        <Time Value=\"{:.17g}\"/>\n", snapshot.frame_times[k]);
    // One vertex cell per particle (connectivity /particles/id), so every representation draws the points.
    text += fmt::format(
        "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{}\" NodesPerElement=\"1\">\n", n);
    text += data_item(file, "/particles/id", scalar_dims, "Int", "          ");
    text += "        </Topology>\n";
    text += "        <Geometry GeometryType=\"XYZ\">\n";
    text += data_item(file, group + "/x", vector_dims, "Float", "          ");
    text += "        </Geometry>\n";
    for (const FieldInfo& info : kFieldInfos) {
      if (info.bit == kFieldX || !(snapshot.fields & info.bit)) continue;
      const bool scalar = info.components == 1, vector = info.components == 3;
      text += attribute(info.name,
                        scalar   ? "Scalar"
                        : vector ? "Vector"
                                 : "Tensor",
                        file, group + "/" + info.name,
                        scalar   ? scalar_dims
                        : vector ? vector_dims
                                 : tensor_dims,
                        "Float");
    }
    text += constants;
    text += "      </Grid>\n";
  }
  text += "    </Grid>\n  </Domain>\n</Xdmf>\n";
  return text;
}

void write_xdmf(const std::string& path, const XdmfSnapshot& snapshot) {
  write_file_atomically(path, xdmf_document(snapshot));
}

}  // namespace romp::io
