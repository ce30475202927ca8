// Box lattice sampling.
#include "host/box_lattice.h"

#include <cmath>
#include <string>

#include "kernels/core/error.h"

namespace romp {

mpm::ParticleInit sample_box_lattice(const Vec3<float>& low, const Vec3<float>& high, float spacing, float density,
                                     std::int32_t material) {
  ROMP_CHECK(spacing > 0.0f && density > 0.0f, "lattice spacing and density must be > 0");
  Index n[3];
  for (int a = 0; a < 3; ++a) {
    n[a] = Index(std::lround((high[a] - low[a]) / spacing));
    ROMP_CHECK(n[a] > 0, "box extent along axis " + std::to_string(a) + " holds no lattice cell");
  }
  const Index count = n[0] * n[1] * n[2];
  const float volume = spacing * spacing * spacing;
  mpm::ParticleInit init;
  init.x.resize(3 * count);
  init.v.assign(3 * count, 0.0f);
  init.mass.assign(count, density * volume);
  init.volume0.assign(count, volume);
  init.material.assign(count, material);
  init.dirichlet_group.assign(count, mpm::kNoDirichletGroup);
  Index p = 0;
  for (Index i = 0; i < n[0]; ++i)
    for (Index j = 0; j < n[1]; ++j)
      for (Index k = 0; k < n[2]; ++k, ++p) {
        const Index ijk[3] = {i, j, k};
        for (int a = 0; a < 3; ++a) init.x[a * count + p] = low[a] + (float(ijk[a]) + 0.5f) * spacing;
      }
  return init;
}

}  // namespace romp
