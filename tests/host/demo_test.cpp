// The built-in demo runs every material of the paper and prints an honest stage table.
#include <gtest/gtest.h>

#include <cmath>

#include "host/demo.h"

namespace romp {
namespace {

TEST(CubeDemo, EveryMaterialStaysFiniteAndInsideTheBox) {
  for (NclawMaterial material : {NclawMaterial::Jelly, NclawMaterial::Sand, NclawMaterial::Plasticine, NclawMaterial::Water}) {
    const DemoResult r = run_cube_demo(Exec::cpu(), material, 100);
    EXPECT_EQ(r.particles, 1000);
    EXPECT_EQ(r.substeps, 100);
    EXPECT_NEAR(r.simulated_seconds, 0.05, 1e-6);
    for (int a = 0; a < 3; ++a) {
      EXPECT_GT(r.center_of_mass[a], 0.0);
      EXPECT_LT(r.center_of_mass[a], 1.0);
    }
    EXPECT_TRUE(std::isfinite(r.kinetic_energy));
    // Plastic materials run the extra stage, elastic ones do not.
    const bool plastic = material != NclawMaterial::Jelly;
    EXPECT_EQ(r.stage_seconds.back().first == "plasticity", plastic);
  }
}

TEST(CubeDemo, StageTableListsSharesAndTotal) {
  const std::string table = stage_table({{"p2g", 3.0}, {"g2p", 1.0}});
  EXPECT_NE(table.find("p2g"), std::string::npos);
  EXPECT_NE(table.find("75.0%"), std::string::npos);
  EXPECT_NE(table.find("total"), std::string::npos);
}

}  // namespace
}  // namespace romp
