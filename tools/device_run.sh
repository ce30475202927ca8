#!/usr/bin/env bash
# Run on a lent GPU machine (device tool: carry [".device"], command `tools/device_run.sh`): one
# prepared run that fits the lease. Builds romp for sm_90 against the machine's PyTorch LibTorch and
# the packages tools/device_prepare.sh unpacked, then runs each stage under its own time cap inside
# one deadline: the gpu-labelled tests, the CPU tests that reach LibTorch, every benchmark suite,
# and CUDA-against-CPU runs of three scenes. What lands in $OUT is at most 8 files:
#   summary.txt   one line per stage (exit code, seconds, cap) and the lines that matter, printed last too
#   logs.tgz      every stage's log (re-packed after each stage, so a run cut short still has them)
#   bench.tgz     romp-bench's CSV and JSON records
# Environment: ROMP_DEVICE_BUDGET seconds for the whole script (default 540), ROMP_DEVICE_ARCH (90),
# ROMP_TORCH_DIR (LibTorch's CMake folder). Exits 1 when any stage failed (.github/workflows/ci.yml).
set -uo pipefail
t0=$(date +%s)
budget=${ROMP_DEVICE_BUDGET:-540}
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${OUT:-$root/device-out}"
work=/tmp/romp-device; logs=$work/logs; records=$work/bench
build_dir="$root/build-device"
mkdir -p "$out" "$logs" "$records"
failed=()
: >"$out/summary.txt"

elapsed() { echo $(( $(date +%s) - t0 )); }
say() { echo "[$(elapsed)s] $*" | tee -a "$out/summary.txt"; }
pack() {
  tar czf "$out/logs.tgz" -C "$work" logs 2>/dev/null
  tar czf "$out/bench.tgz" -C "$work" bench 2>/dev/null
}
# cap N: N seconds, or what is left before the deadline less a margin for packing.
cap() { local left=$(( budget - $(elapsed) - 15 )); (( left < $1 )) && echo $(( left > 0 ? left : 0 )) || echo "$1"; }
# stage NAME CAP CMD...: runs CMD under its cap with its output in logs/NAME.log; records rc and time.
stage() {
  local name=$1 limit; limit=$(cap "$2"); shift 2
  if (( limit <= 5 )); then say "$name: skipped (deadline)"; return 99; fi
  local started; started=$(date +%s)
  timeout -k 5 "$limit" "$@" >"$logs/$name.log" 2>&1
  local rc=$?
  (( rc == 0 )) || failed+=("$name")
  say "$name: rc=$rc in $(( $(date +%s) - started ))s (cap ${limit}s)"
  pack
  return $rc
}
# quote LOG PATTERN [N]: the first N lines of LOG matching PATTERN, into the summary.
quote() { grep -E "$2" "$logs/$1.log" 2>/dev/null | head -"${3:-20}" | tee -a "$out/summary.txt"; }

# Packages: unpacked by device_prepare.sh under .device (a bare lent machine), else the system's
# (a runner set up with tools/setup.sh).
prefix="$root/.device/root/usr"
lib="$prefix/lib/x86_64-linux-gnu"
packages=()
if [ -d "$prefix" ]; then
  # device_prepare.sh's links point into the checkout of the machine that made them.
  find "$root/.device/root" -type l | while read -r link; do
    target=$(readlink "$link")
    case "$target" in */.device/root/*) ln -sfn "$root/.device/root/${target#*/.device/root/}" "$link" ;; esac
  done
  # HDF5's own dependencies, only those the machine lacks: shadowing its libcrypto or libz would
  # break its Python and CMake.
  mkdir -p "$root/.device/missing"
  for f in "$root"/.device/extra/*.so*; do
    [ -e "$f" ] || continue
    name=$(basename "$f")
    ldconfig -p | awk '{print $1}' | grep -qx "$name" || ln -sfn "$f" "$root/.device/missing/$name"
  done
  say "packages from .device; libraries supplied: $(ls "$root/.device/missing" | tr '\n' ' ')"
  export LD_LIBRARY_PATH="$lib:$lib/hdf5/serial:$root/.device/missing${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  packages=(-DCMAKE_PREFIX_PATH="$prefix;$lib/cmake" -DEigen3_DIR="$prefix/share/eigen3/cmake"
    -DHDF5_C_COMPILER_EXECUTABLE= -DHDF5_C_INCLUDE_DIR="$prefix/include/hdf5/serial"
    -DHDF5_C_LIBRARY_hdf5="$lib/hdf5/serial/libhdf5.so")
else
  say "packages from the system (no .device/: tools/device_prepare.sh was not carried)"
fi
export PATH="/usr/local/cuda/bin:$PATH"
export OMP_WAIT_POLICY=passive

say "commit $(git -C "$root" rev-parse --short=12 HEAD 2>/dev/null || cat "$root/cmake/archive_commit.txt")"
{
  nvidia-smi
  nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm,clocks.mem --format=csv
  nvcc --version; cmake --version; g++ --version; cat /etc/os-release; nproc; free -g
  python3 -c 'import torch, sys; print(sys.executable, torch.__version__, torch.version.cuda)'
} >"$logs/env.log" 2>&1
quote env "NVIDIA H|release|g\+\+|PRETTY|torch|^[0-9]+$" 12
# LibTorch: ROMP_TORCH_DIR (tools/torch_wheel.sh prints one), else the PyTorch of the machine's python3.
torch_dir=${ROMP_TORCH_DIR:-$(python3 -c 'import torch.utils, os; print(os.path.join(torch.utils.cmake_prefix_path, "Torch"))' 2>/dev/null)}

stage configure 120 cmake -S "$root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DROMP_CUDA=ON \
  -DROMP_CUDA_ARCHITECTURES="${ROMP_DEVICE_ARCH:-90}" ${torch_dir:+-DTorch_DIR="$torch_dir"} \
  "${packages[@]}" || { quote configure "Error|error" 30; pack; exit 1; }
quote configure "^-- romp 0"
# -k 0: one file this compiler refuses costs only what depends on it.
stage build 330 cmake --build "$build_dir" -j "$(nproc)" -- -k 0
quote build "error|FAILED" 30

romp="$build_dir/romp"; bench="$build_dir/romp-bench"
if [ -x "$romp" ]; then
  stage info 20 "$romp" info && quote info "commit|CUDA|LibTorch|device"
  stage ctest_gpu 150 ctest --test-dir "$build_dir" -L gpu -j 8 --timeout 60 --output-on-failure
  quote ctest_gpu "tests passed|tests failed|\((Failed|Timeout|SEGFAULT)\)" 40
  stage ctest_cpu 150 ctest --test-dir "$build_dir" -LE gpu -j "$(nproc)" --timeout 90 --output-on-failure
  quote ctest_cpu "tests passed|tests failed|\((Failed|Timeout|SEGFAULT)\)" 40
fi
if [ -x "$bench" ]; then
  b() { local name=$1 limit=$2; shift 2; stage "bench_$name" "$limit" "$bench" --device cuda --out "$records" --name "$name" "$@"; }
  b mem_svd 40 --suite memory --suite svd --repeats 10 --warmup 2
  b step4 120 --suite step --scale 4 --repeats 5 --warmup 1
  # Scenes of 1k and 4k particles a frame at a time, batches as graphs and launched (the 50 µs target).
  quote bench_step4 "_frames|us_per_substep" 12
  # The same with every one-element launch in blocks of 256, as before the occupancy calculator chose them
  # (gpu-notes.md, "Loads in flight"): the block size's A/B on one machine.
  ROMP_FOR_EACH_BLOCK_SIZE=256 b step4_block256 90 --suite step --scale 4 --repeats 3 --warmup 1
  b mlp 40 --suite mlp --repeats 10 --warmup 2
  b rom_cost_tower 90 --suite rom-cost --scene "$root/scenes/rom/tower.toml" --set dx=0.0048 \
    --rom-samples 10 --rom-samples 50 --repeats 3 --warmup 1
  # Each case's time and its launches and transfers (gpu-notes.md's predictions check against these).
  quote bench_rom_cost_tower "median|host traffic" 24
  b quadrature 40 --suite quadrature --repeats 3 --warmup 1
  b train 60 --suite train --repeats 2 --warmup 1
fi
if [ -x "$romp" ]; then
  # Each scene on both backends, then the CUDA run's accumulated position error against the CPU's.
  against_cpu() {
    local name=$1 limit=$2; shift 2
    stage "run_${name}_cuda" "$limit" "$romp" --device cuda run "$@" -o "$work/${name}_cuda.h5" --no-progress &&
      stage "run_${name}_cpu" "$limit" "$romp" --device cpu run "$@" -o "$work/${name}_cpu.h5" --no-progress &&
      stage "compare_$name" 20 "$romp" compare "$work/${name}_cuda.h5" "$work/${name}_cpu.h5" &&
      quote "compare_$name" "error" 3
  }
  against_cpu default 40 "$root/scenes/default.toml"
  # The default scene's batches replayed as graphs (the run above) against the same batches launched substep by
  # substep: gpu-notes.md, "Full-order batches of substeps as one CUDA graph".
  stage run_default_no_graphs 40 "$romp" --device cuda run "$root/scenes/default.toml" --no-frame-graphs \
    -o "$work/default_no_graphs.h5" --no-progress
  quote run_default_cuda "substeps|batches" 6
  quote run_default_no_graphs "substeps|batches" 6
  against_cpu sand 60 "$root/scenes/nclaw/cube_sand.toml"
  against_cpu pool_neural 90 "$root/scenes/nclaw/jelly_into_water_pool.toml" --law "jelly=$root/scenes/nclaw/laws/jelly.h5"
  stage run_robust_cuda 60 "$romp" --device cuda run "$root/scenes/robust/twist_compress_release.toml" \
    -o "$work/robust_cuda.h5" --no-progress
fi
# Hardware counters of the transfer kernels, with what is left: local-memory sectors (0 predicted since the
# stencil loops are unrolled, gpu-notes.md), achieved occupancy and time, for the step suite's first cases.
if command -v ncu >/dev/null && [ -x "$bench" ]; then
  stage ncu_transfers 60 ncu --clock-control none --kernel-name-base demangled \
    --kernel-name 'regex:ParticleToGrid|GridToParticle|tiled_block_to_grid' --launch-count 60 \
    --metrics gpu__time_duration.sum,sm__warps_active.avg.pct_of_peak_sustained_active,l1tex__t_sectors_pipe_lsu_mem_local_op_ld.sum,l1tex__t_sectors_pipe_lsu_mem_local_op_st.sum,dram__throughput.avg.pct_of_peak_sustained_elapsed \
    "$bench" --device cuda --suite step --scale 1 --repeats 1 --warmup 0 --out "$work/ncu-bench" --name ncu
  quote ncu_transfers "ParticleToGrid|GridToParticle|tiled_block|local_op|warps_active|duration" 40
fi
pack
say "done; ${#failed[@]} stages failed${failed[*]:+: ${failed[*]}}"
echo "===== summary"
cat "$out/summary.txt"
(( ${#failed[@]} == 0 ))
