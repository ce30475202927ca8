// XDMF sidecars: every HDF5 reference resolves to a dataset of the stated dimensions, in the file that
// exists at that moment (the .partial file during a run, the final one after).
#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <regex>
#include <sstream>

#include "nn/io/hdf5_file.h"
#include "nn/io/snapshot_writer.h"
#include "nn/io/xdmf.h"
#include "tests/nn/io/io_test_support.h"

namespace romp::io::testing {
namespace {

using Xdmf = IoTest;

struct Reference {
  std::string dimensions, file, dataset;
};

// The DataItems of a sidecar, read with a regular expression (the writer puts each on one line).
std::vector<Reference> references(const std::string& xml) {
  static const std::regex item(R"re(<DataItem Dimensions="([0-9 ]+)"[^>]*Format="HDF">([^<:]+):(/[^<]+)</DataItem>)re");
  std::vector<Reference> found;
  for (auto match = std::sregex_iterator(xml.begin(), xml.end(), item); match != std::sregex_iterator(); ++match) {
    found.push_back({(*match)[1], (*match)[2], (*match)[3]});
  }
  return found;
}

io::hdf5::Shape parse_dimensions(const std::string& text) {
  std::istringstream in(text);
  io::hdf5::Shape shape;
  for (std::uint64_t extent; in >> extent;) shape.push_back(extent);
  return shape;
}

// Checks every reference in `sidecar` against the HDF5 file it names, relative to the sidecar's folder.
void expect_references_resolve(const std::filesystem::path& sidecar, const std::string& expected_file,
                               std::size_t expected_count) {
  const std::vector<Reference> found = references(read_file(sidecar.string()));
  EXPECT_EQ(found.size(), expected_count);
  for (const Reference& reference : found) {
    ASSERT_EQ(reference.file, expected_file);
    const io::hdf5::File file =
        io::hdf5::File::open((sidecar.parent_path() / reference.file).string(), io::hdf5::Mode::ReadOnly, "snapshot");
    ASSERT_TRUE(file.is_dataset(reference.dataset)) << reference.dataset;
    EXPECT_EQ(file.dataset_shape(reference.dataset), parse_dimensions(reference.dimensions)) << reference.dataset;
  }
}

TEST_F(Xdmf, SidecarReferencesDatasetsThatExist) {
  std::mt19937 random(31);
  const std::string path = file("run.h5");
  SnapshotWriter writer(path, random_header(30, random), kAllFields);
  const std::filesystem::path sidecar = xdmf_path(path);
  EXPECT_EQ(sidecar, folder_.path() / "run.xdmf");
  // Per frame: topology, geometry, the nine fields besides x, and the six per-particle constants (X, mass,
  // volume0, material, group, id).
  expect_references_resolve(sidecar, "run.h5.partial", 0);
  for (int k = 0; k < 3; ++k) writer.append_frame(random_frame(30, 0.5 * k, k, random));
  expect_references_resolve(sidecar, "run.h5.partial", 3 * 17);
  writer.finish();
  expect_references_resolve(sidecar, "run.h5", 3 * 17);
}

TEST_F(Xdmf, SidecarIsATemporalCollectionOfPointClouds) {
  XdmfSnapshot snapshot;
  snapshot.hdf5_file = "a&b.h5";
  snapshot.particle_count = 7;
  snapshot.fields = kFieldX | kFieldF;
  snapshot.frame_times = {0.0, 0.1};
  const std::string xml = xdmf_document(snapshot);
  EXPECT_NE(xml.find(R"(<Grid Name="particles" GridType="Collection" CollectionType="Temporal">)"), std::string::npos);
  EXPECT_NE(xml.find(R"(<Time Value="0.10000000000000001"/>)"), std::string::npos);
  EXPECT_NE(xml.find(R"(<Topology TopologyType="Polyvertex" NumberOfElements="7" NodesPerElement="1">)"),
            std::string::npos);
  EXPECT_NE(xml.find(R"(<Attribute Name="F" AttributeType="Tensor" Center="Node">)"), std::string::npos);
  EXPECT_NE(xml.find(R"(Dimensions="7 3 3")"), std::string::npos);
  EXPECT_EQ(xml.find(R"(Name="v")"), std::string::npos);  // not selected
  EXPECT_NE(xml.find("a&amp;b.h5:/frames/000001/x"), std::string::npos);
}

}  // namespace
}  // namespace romp::io::testing
