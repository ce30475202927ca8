// DomainInit: the host-side description of the hexahedral particle domains of a scene.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/core/exec.h"
#include "kernels/mpm/hex_domain.h"

namespace romp::mpm {

inline constexpr std::int32_t kNoDomain = -1;

// Domains and their shared corners. Neighbouring particles of one body share corners, which is what
// keeps them together under stretching (no numerical fracture). Per-domain arrays hold 8 entries
// per domain, corner α of domain d at 8 d + α (α as in hex_domain.h).
struct DomainInit {
  std::vector<float> corner_x;                       // 3 planes over the corners (m)
  std::vector<std::int32_t> corner_dirichlet_group;  // per corner: a prescribed motion, or kNoDirichletGroup
  std::vector<std::int32_t> corner;                  // 8 per domain: corner indices
  std::vector<float> weight;                         // 8 per domain: ω_αp
  std::vector<float> gradient;                       // 3 per entry: g_αp as (x, y, z) (1/m); kernels see planes
  // A run resumed from a checkpoint starts from the corners' positions then (3 planes; empty: at
  // corner_x, which stays the reference configuration) and from the domain_stiffening of the substep
  // before (1 at rest), which the first CFL step reads.
  std::vector<float> resumed_corner_x;
  float stiffening = 1.0f;

  Index count() const { return Index(corner.size()) / kDomainCorners; }
  // Corner α of domain d in `planes`: 3 planes over the corners, corner_x or a later state of it.
  Vec3<double> corner_position(const std::vector<float>& planes, Index d, int alpha) const {
    const Index n = corner_count();
    const std::size_t c = std::size_t(corner[std::size_t(kDomainCorners * d + alpha)]);
    return Vec3<double>(planes[c], planes[std::size_t(n) + c], planes[2 * std::size_t(n) + c]);
  }
  Index corner_count() const { return Index(corner_dirichlet_group.size()); }
  bool empty() const { return corner.empty(); }
};

}  // namespace romp::mpm
