// The configuration of an MPM simulation: grid, time stepping, materials, boundaries and loads, as
// scene_setup builds it from a scene. FullOrderSim and ReducedSim take the same configuration.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "kernels/core/exec.h"
#include "kernels/mpm/domain_config.h"
#include "kernels/mpm/step.h"

namespace romp::engine {

struct MaterialSpec {
  material::MaterialParams<float> params;
  float density = 1000.0f;  // kg/m^3, for the wave speed of the CFL condition
  // The law file (romp-neural-law) of a MaterialModel::Neural material; empty for every other.
  std::string neural_law;
  // While strength_off_from <= t < strength_off_until the material has no stiffness (μ = λ = 0): a
  // body collapses under its loads, and recovers when its strength returns (the enriched-MPM
  // paper's Fig. 5). Hyperelastic models only; an empty window by default.
  double strength_off_from = 0.0, strength_off_until = 0.0;
  bool strength_off_at(double t) const { return t >= strength_off_from && t < strength_off_until; }
};

// A collider's pose at t = 0 and its constant rigid motion: center(t) = center + v t,
// rotation(t) = exp(t [ω]×) rotation(0). It acts while t < end.
struct ColliderSpec {
  mpm::ColliderState initial;
  double end = std::numeric_limits<double>::infinity();
};

// Particles of a Dirichlet group follow v(x) = v_lin + ω × (x − pivot(t)), pivot(t) = pivot + v_lin t,
// until `end`, when they are released to move freely for the rest of the run.
struct DirichletSpec {
  Vec3<float> pivot;
  Vec3<float> linear_velocity;
  Vec3<float> angular_velocity;
  double end = std::numeric_limits<double>::infinity();
};

// Particles inside `region` while start <= t < end lose their domains for good (mpm::release_domains).
struct DomainReleaseSpec {
  mpm::Region region;
  double start = 0.0;
  double end = std::numeric_limits<double>::infinity();
};

// A surface traction on the particles a scene assigned to it at t = 0 (ParticleInit::traction), for
// start <= t < end.
struct TractionSpec {
  Vec3<float> traction;  // Pa, force per reference area
  double start = 0.0;    // s
  double end = std::numeric_limits<double>::infinity();
};

struct RegionLoadSpec {
  mpm::RegionLoad load;
  double start = 0.0;  // s; the load acts for start <= t < end
  double end = 0.0;
};

// How P2G reaches the grid: per particle and node (the portable reference), or per grid block through a
// local tile of nodes (fewer atomics; see kernels/mpm/p2g_tiled.cu).
enum class P2GKernel { Portable, Tiled };

// Where plastic materials' return map runs: in a pass of its own after G2P (the reference), or in G2P as each
// particle's F is updated, with the same arithmetic and so the same results, and one pass less over F and the
// plastic state. Scenes with particle domains keep the pass (their particles move after G2P).
enum class ReturnMapPass { Separate, InG2P };

// How the grid velocities advance: explicit symplectic Euler, or one Newton step of backward Euler
// solved by CG on the grid (host/implicit_grid_solver.h), which is stable beyond the explicit CFL limit.
enum class Integrator { Explicit, Implicit };

// Whether runs of substeps are replayed as CUDA graphs where the step allows (kernels/core/stream_graph.h).
// Auto: on CUDA only. On the CPU a replay runs the same loops, saves nothing (a CPU launch costs nothing) and
// folds the stage table's rows into one; Always replays there too (the tests check a replay's semantics on
// the CPU). Never: launched substep by substep (romp run --no-frame-graphs), with the same results.
enum class GraphReplay { Auto, Always, Never };
inline bool replays_graphs(GraphReplay choice, const Exec& exec) {
  return choice == GraphReplay::Always || (choice == GraphReplay::Auto && exec.is_cuda());
}

// The largest cfl the implicit step accepts: it lifts the elastic wave limit, so Δt may span many
// wave crossings of a cell; particles are still kept within a cell per step (FullOrderSim::stable_dt).
inline constexpr float kImplicitMaxCfl = 20.0f;

// The implicit step's CG: converged when ‖r‖ ≤ tolerance ‖M v*‖ (the momentum on the unknowns),
// else it keeps the explicit velocities after max_iterations.
struct ImplicitSolverConfig {
  float tolerance = 1e-6f;
  std::int32_t max_iterations = 1000;
};

// Substeps between block sorts on CUDA when the scene leaves it open: the sort and the permutation of every
// particle array are about half of a substep's bytes (bench/results/gpu-notes.md), and a particle takes
// several substeps to cross a 4-node block at a CFL step.
inline constexpr int kSortEveryOnCuda = 4;

// The domain, grid, walls, gravity and time stepping (mpm::DomainConfig), then the engine's own.
struct FullOrderConfig : mpm::DomainConfig<float> {
  mpm::Transfer transfer = mpm::Transfer::Apic;
  float flip_alpha = 0.95f;
  P2GKernel p2g = P2GKernel::Tiled;
  ReturnMapPass return_map = ReturnMapPass::InG2P;
  // Substeps between sorts of the particles by grid block (≥ 1; 0: the backend's choice, 1 on the CPU, where
  // a run resumed from a checkpoint must sum in the uninterrupted run's order, and kSortEveryOnCuda there but
  // for scenes of few particles, FullOrderSim::counts_on_device, which sort every substep).
  // Between sorts the tiled P2G sends particles that left their block straight to the grid, and (without particle
  // domains or tracers) the grid built around the particles' blocks at the sort serves; a particle whose
  // stencil leaves it makes the next substep sort early.
  int sort_every = 0;
  // Batches of substeps (FullOrderSim::runs_batches) replayed as one CUDA graph each (GraphReplay). Not a scene
  // key.
  GraphReplay frame_graphs = GraphReplay::Auto;
  // Particle domains: corners of particles whose deformation quality (particle_domains.h) is at most
  // this become degrees of freedom of their own (dynamic enrichment); 0 turns enrichment off.
  float enrichment_threshold = 0.6f;
  Integrator integrator = Integrator::Explicit;
  ImplicitSolverConfig implicit;
  std::vector<MaterialSpec> materials;
  std::vector<ColliderSpec> colliders;
  std::vector<DirichletSpec> dirichlet;
  std::vector<RegionLoadSpec> loads;
  std::vector<TractionSpec> tractions;
  std::vector<DomainReleaseSpec> domain_releases;
};

}  // namespace romp::engine
