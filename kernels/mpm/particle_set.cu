// ParticleSet: upload of the initial state, block sort, and read-back in the initial order.
#include "kernels/mpm/particle_set.h"

#include <algorithm>
#include <numeric>
#include <utility>

#include "kernels/core/error.h"
#include "kernels/core/for_each.h"
#include "kernels/core/gather_planes.h"
#include "kernels/core/memory.h"
#include "kernels/core/replace_value.h"
#include "kernels/mpm/sparse_grid.h"

#if defined(__CUDACC__)
#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_run_length_encode.cuh>
#include <cub/device/device_scan.cuh>

#include "kernels/core/cuda_check.h"
#endif

namespace romp::mpm {
namespace {

struct SetIdentity {
  Mat3Planes<float> F;
  ROMP_HD void operator()(Index p) const { F.store(p, Mat3<float>::identity()); }
};

struct SetIota {
  Span<std::int32_t> id;
  ROMP_HD void operator()(Index p) const { id[p] = std::int32_t(p); }
};

struct BlockKeyOfParticle {
  Vec3Planes<const float> x;
  Span<std::uint64_t> keys;
  Span<std::int32_t> order;
  float inverse_dx;
  ROMP_HD void operator()(Index p) const {
    keys[p] = particle_block_key(x.load(p), inverse_dx);
    order[p] = std::int32_t(p);
  }
};

// The inverse of a gather through a permutation: destination[c n + index[i]] = source[c n + i].
template <class T>
struct ScatterPlanes {
  Span<const T> source;
  Span<T> destination;
  Span<const std::int32_t> index;
  int components;
  ROMP_HD void operator()(Index i) const {
    const Index n = index.size();
    copy_row(source.data(), n, i, destination.data(), n, index[i], components);
  }
};

// `buffer` as `n` elements: reallocated only when its size differs (the particle count is fixed).
template <class T>
DeviceBuffer<T>& sized(DeviceBuffer<T>& buffer, Backend backend, Index n) {
  if (buffer.size() != n) buffer = DeviceBuffer<T>(backend, n);
  return buffer;
}

// planes ← planes gathered through `order`, by way of `spare` (same size afterwards: the two swap).
template <class T>
void permute(const Exec& exec, DeviceBuffer<T>& planes, int components, Span<const std::int32_t> order,
             DeviceBuffer<T>& spare) {
  sized(spare, planes.backend(), planes.size());
  for_each(exec, order.size(), GatherPlanes<T>{planes.span(), order.size(), spare.span(), order, components});
  std::swap(planes, spare);
}

// Every real and integer plane of particle i gathered through the sort's order, in one pass.
struct GatherParticle {
  GatherPlanes<float> reals;
  GatherPlanes<std::int32_t> integers;
  ROMP_HD void operator()(Index i) const {
    reals(i);
    integers(i);
  }
};

#if defined(__CUDACC__)
// CUB's temporary storage of `bytes`, grown when short.
void* temporary_storage(BlockSortScratch& scratch, Backend backend, std::size_t bytes) {
  scratch.temporary.ensure_size(backend, Index(bytes));
  return scratch.temporary.data();
}
#endif

// Zeroes the run lengths past the runs Encode found (what it leaves there is not specified), so that their
// sum stops growing at n.
struct ZeroPastRuns {
  Span<std::int32_t> lengths;
  Span<const std::int64_t> runs;
  ROMP_HD void operator()(Index i) const {
    if (i >= runs[0]) lengths[i] = 0;
  }
};

// Into `starts` (n + 1 entries): the start of every run of equal keys in sorted scratch.keys, then n in every
// entry past the runs (runs past the count are empty); into scratch.run_count, on the device, their number.
void find_runs(const Exec& exec, BlockSortScratch& scratch, DeviceBuffer<std::int32_t>& starts) {
  const DeviceBuffer<std::uint64_t>& keys = scratch.keys;
  const Index n = keys.size();
  const Backend backend = keys.backend();
  DeviceBuffer<std::int64_t>& runs = sized(scratch.run_count, backend, 1);
  if (exec.is_cuda()) {
#if defined(__CUDACC__)
    // Run lengths, then their exclusive sum over all n + 1 slots: entry `runs` and every later one is then n.
    DeviceBuffer<std::uint64_t>& unique = sized(scratch.unique_keys, backend, n);
    DeviceBuffer<std::int32_t>& lengths = sized(scratch.run_lengths, backend, n + 1);
    memory::note_launch(2);  // Encode and the scan (ZeroPastRuns counts itself)
    std::size_t bytes = 0;
    ROMP_CUDA_CHECK(cub::DeviceRunLengthEncode::Encode(nullptr, bytes, keys.data(), unique.data(), lengths.data(),
                                                       runs.data(), int(n), exec.stream));
    ROMP_CUDA_CHECK(cub::DeviceRunLengthEncode::Encode(temporary_storage(scratch, backend, bytes), bytes, keys.data(),
                                                       unique.data(), lengths.data(), runs.data(), int(n),
                                                       exec.stream));
    for_each(exec, n + 1, ZeroPastRuns{lengths.span(), runs.span()});
    bytes = 0;
    ROMP_CUDA_CHECK(
        cub::DeviceScan::ExclusiveSum(nullptr, bytes, lengths.data(), starts.data(), int(n + 1), exec.stream));
    ROMP_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(temporary_storage(scratch, backend, bytes), bytes, lengths.data(),
                                                  starts.data(), int(n + 1), exec.stream));
    return;
#else
    throw Error("find_runs on CUDA from a translation unit not compiled by nvcc");
#endif
  }
  // The CPU's stand-in for Encode, ZeroPastRuns and the scan, counted as their launches.
  memory::launch_on_cpu(exec.stream, 3, [keys = keys.span(), starts = starts.span(), runs = runs.span()] {
    const memory::DeviceAccess launch;
    const Index n = keys.size();
    std::int32_t count = 0;
    for (Index p = 0; p < n; ++p)
      if (p == 0 || keys[p] != keys[p - 1]) starts[count++] = std::int32_t(p);
    std::fill(starts.data() + count, starts.data() + n + 1, std::int32_t(n));
    runs[0] = count;
  });
}

// Sorts scratch.order by scratch.keys, and on CUDA the keys with it (the CPU sort orders `order` alone).
void sort_pairs(const Exec& exec, BlockSortScratch& scratch, Span<const std::int32_t> id) {
  DeviceBuffer<std::uint64_t>& keys = scratch.keys;
  DeviceBuffer<std::int32_t>& order = scratch.order;
  const Index n = keys.size();
  if (exec.is_cuda()) {
#if defined(__CUDACC__)
    memory::note_launch();  // DeviceRadixSort
    const Backend backend = keys.backend();
    DeviceBuffer<std::uint64_t>& keys_out = sized(scratch.sorted_keys, backend, n);
    DeviceBuffer<std::int32_t>& order_out = sized(scratch.sorted_order, backend, n);
    constexpr int kKeyBitCount = 3 * kKeyBits;  // the tag bit is the same for every key
    std::size_t temporary_bytes = 0;
    ROMP_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(nullptr, temporary_bytes, keys.data(), keys_out.data(),
                                                    order.data(), order_out.data(), int(n), 0, kKeyBitCount,
                                                    exec.stream));
    ROMP_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(temporary_storage(scratch, backend, temporary_bytes),
                                                    temporary_bytes, keys.data(), keys_out.data(), order.data(),
                                                    order_out.data(), int(n), 0, kKeyBitCount, exec.stream));
    std::swap(keys, keys_out);
    std::swap(order, order_out);
    return;
#else
    throw Error("sort_pairs on CUDA from a translation unit not compiled by nvcc");
#endif
  }
  // CPU: ties broken by the initial index (unique), so the permutation does not depend on the order
  // the particles arrived in.
  memory::launch_on_cpu(exec.stream, 1, [k = keys.span(), initial = id, order = order.span()] {
    const memory::DeviceAccess launch;  // the CPU's stand-in for the device sort
    std::sort(order.begin(), order.end(), [k, initial](std::int32_t a, std::int32_t b) {
      return k[a] < k[b] || (k[a] == k[b] && initial[a] < initial[b]);
    });
  });
}

}  // namespace

ParticleSet::ParticleSet(Backend backend, const ParticleInit& init) : backend_(backend), count_(init.count()) {
  const Index n = count_;
  ROMP_CHECK(n > 0, "a particle set needs at least one particle");
  ROMP_CHECK(Index(init.x.size()) == 3 * n && Index(init.v.size()) == 3 * n,
             "particle positions and velocities need 3 planes of " + std::to_string(n));
  ROMP_CHECK((init.F.empty() || Index(init.F.size()) == 9 * n) && (init.C.empty() || Index(init.C.size()) == 9 * n),
             "particle F and C need 9 planes of " + std::to_string(n) + " (or none)");
  ROMP_CHECK(
      Index(init.volume0.size()) == n && Index(init.material.size()) == n && Index(init.dirichlet_group.size()) == n,
      "every per-particle array needs " + std::to_string(n) + " entries");
  ROMP_CHECK(init.domain.empty() || Index(init.domain.size()) == n,
             "the per-particle domain index needs " + std::to_string(n) + " entries (or none)");
  ROMP_CHECK(init.plastic.empty() || Index(init.plastic.size()) == 2 * n,
             "the plastic state needs 2 planes of " + std::to_string(n) + " (or none)");
  reals_ = DeviceBuffer<float>(backend, (init.plastic.empty() ? kRealPlanes : kPlasticRealPlanes) * n);
  reals_.fill_zero();  // C = 0 unless given
  auto upload_planes = [&](const std::vector<float>& host, int first, int planes) {
    upload(backend, reals(first, planes), Span<const float>(host.data(), Index(host.size())));
  };
  upload_planes(init.x, kX, 3);
  upload_planes(init.v, kV, 3);
  if (!init.C.empty()) upload_planes(init.C, kC, 9);
  if (!init.F.empty()) upload_planes(init.F, kF, 9);
  upload_planes(init.mass, kMass, 1);
  upload_planes(init.volume0, kVolume0, 1);
  if (!init.plastic.empty()) upload_planes(init.plastic, kJp, 2);
  ROMP_CHECK(init.traction.empty() || Index(init.traction.size()) == n,
             "the per-particle traction index needs " + std::to_string(n) + " entries (or none)");
  int integer_planes = kFixedIntegerPlanes;
  if (!init.domain.empty()) domain_plane_ = integer_planes++;
  if (!init.traction.empty()) traction_plane_ = integer_planes++;
  integers_ = DeviceBuffer<std::int32_t>(backend, integer_planes * n);
  auto upload_integers = [&](const std::vector<std::int32_t>& host, int plane) {
    upload(backend, integers(plane), Span<const std::int32_t>(host.data(), Index(host.size())));
  };
  upload_integers(init.material, kMaterial);
  upload_integers(init.dirichlet_group, kDirichletGroup);
  if (domain_plane_ >= 0) upload_integers(init.domain, domain_plane_);
  if (traction_plane_ >= 0) upload_integers(init.traction, traction_plane_);
  const Exec exec = backend == Backend::Cuda ? Exec::cuda() : Exec::cpu();
  if (init.F.empty()) for_each(exec, n, SetIdentity{Mat3Planes<float>(reals(kF, 9).data(), n)});
  for_each(exec, n, SetIota{integers(kId)});
  synchronize(exec);
}

ParticleView ParticleSet::view() {
  const Index n = count_;
  return ParticleView{n,
                      Vec3Planes<float>(reals(kX, 3).data(), n),
                      Vec3Planes<float>(reals(kV, 3).data(), n),
                      Mat3Planes<float>(reals(kC, 9).data(), n),
                      Mat3Planes<float>(reals(kF, 9).data(), n),
                      reals(kMass, 1),
                      reals(kVolume0, 1),
                      integers(kMaterial),
                      integers(kDirichletGroup),
                      integers(kId),
                      has_domains() ? integers(domain_plane_) : Span<std::int32_t>(),
                      has_plastic_state() ? reals(kJp, 1) : Span<float>(),
                      has_plastic_state() ? reals(kPlasticStrain, 1) : Span<float>(),
                      traction_plane_ >= 0 ? integers(traction_plane_) : Span<std::int32_t>()};
}

std::size_t ParticleSet::bytes() const { return reals_.bytes() + integers_.bytes(); }

void ParticleSet::sort_by_block(const Exec& exec, float inverse_dx, RunCount run_count) {
  const Index n = count_;
  BlockSortScratch& scratch = sort_scratch_;
  DeviceBuffer<std::uint64_t>& keys = sized(scratch.keys, backend_, n);
  DeviceBuffer<std::int32_t>& order = sized(scratch.order, backend_, n);
  for_each(exec, n,
           BlockKeyOfParticle{Vec3Planes<const float>(reals(kX, 3).data(), n), keys.span(), order.span(), inverse_dx});
  sort_pairs(exec, scratch, integers(kId));
  if (!exec.is_cuda()) permute(exec, keys, 1, order.span(), scratch.sorted_keys);  // the CPU sort orders `order` alone
  if (block_starts_.size() < n + 1) block_starts_ = DeviceBuffer<std::int32_t>(backend_, n + 1);
  find_runs(exec, scratch, block_starts_);
  block_bound_ = run_count == RunCount::ReadBack ? Index(scratch.run_count.to_host(exec.stream)[0]) : n;
  const Span<const std::int32_t> by_block = order.span();
  DeviceBuffer<float>& reals = sized(scratch.reals, backend_, reals_.size());
  DeviceBuffer<std::int32_t>& integers = sized(scratch.integers, backend_, integers_.size());
  for_each(exec, n,
           GatherParticle{
               GatherPlanes<float>{reals_.span(), n, reals.span(), by_block, int(reals_.size() / n)},
               GatherPlanes<std::int32_t>{integers_.span(), n, integers.span(), by_block, int(integers_.size() / n)}});
  if (run_count == RunCount::OnDevice) {
    memory::copy(reals_.data(), backend_, reals.data(), backend_, reals.bytes(), exec.stream);
    memory::copy(integers_.data(), backend_, integers.data(), backend_, integers.bytes(), exec.stream);
  } else {
    std::swap(reals_, reals);
    std::swap(integers_, integers);
  }
}

void ParticleSet::save(const Exec& exec, Snapshot& snapshot) const {
  memory::copy(sized(snapshot.reals, backend_, reals_.size()).data(), backend_, reals_.data(), backend_, reals_.bytes(),
               exec.stream);
  memory::copy(sized(snapshot.integers, backend_, integers_.size()).data(), backend_, integers_.data(), backend_,
               integers_.bytes(), exec.stream);
}

void ParticleSet::restore(const Exec& exec, const Snapshot& snapshot) {
  ROMP_CHECK(snapshot.reals.size() == reals_.size() && snapshot.integers.size() == integers_.size(),
             "ParticleSet::restore: a snapshot of this particle set (save it first)");
  memory::copy(reals_.data(), backend_, snapshot.reals.data(), backend_, reals_.bytes(), exec.stream);
  memory::copy(integers_.data(), backend_, snapshot.integers.data(), backend_, integers_.bytes(), exec.stream);
}

void ParticleSet::release_dirichlet_group(const Exec& exec, std::int32_t group) {
  for_each(exec, count_, ReplaceValue<std::int32_t>{integers(kDirichletGroup), group, kNoDirichletGroup});
}

template <class T>
std::vector<T> ParticleSet::planes_in_initial_order(const Exec& exec, Span<const T> planes, int components) const {
  DeviceBuffer<T> ordered(backend_, planes.size());
  for_each(exec, count_, ScatterPlanes<T>{planes, ordered.span(), integers(kId), components});
  return ordered.to_host(exec.stream);
}

std::vector<float> ParticleSet::positions_in_initial_order(const Exec& exec) const {
  return planes_in_initial_order<float>(exec, reals(kX, 3), 3);
}
std::vector<float> ParticleSet::velocities_in_initial_order(const Exec& exec) const {
  return planes_in_initial_order<float>(exec, reals(kV, 3), 3);
}
std::vector<float> ParticleSet::deformation_gradients_in_initial_order(const Exec& exec) const {
  return planes_in_initial_order<float>(exec, reals(kF, 9), 9);
}
std::vector<float> ParticleSet::affine_velocities_in_initial_order(const Exec& exec) const {
  return planes_in_initial_order<float>(exec, reals(kC, 9), 9);
}
std::vector<float> ParticleSet::plastic_state_in_initial_order(const Exec& exec) const {
  return has_plastic_state() ? planes_in_initial_order<float>(exec, reals(kJp, 2), 2) : std::vector<float>{};
}
std::vector<std::int32_t> ParticleSet::domains_in_initial_order(const Exec& exec) const {
  return has_domains() ? planes_in_initial_order<std::int32_t>(exec, integers(domain_plane_), 1)
                       : std::vector<std::int32_t>{};
}

}  // namespace romp::mpm
