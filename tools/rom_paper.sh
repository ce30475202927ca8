#!/usr/bin/env bash
# The ROM paper's experiments end to end (Chen et al. 2023), one command each: the parameter sweep at
# the paper's resolution, the training of the deformation map, the reduced-order runs on the sweep's
# test members, and `romp compare` of each against the member's full-order run. Prints a markdown
# table: the accumulated position error, mean over the test members (worst in parentheses).
#
#   tools/rom_paper.sh EXPERIMENT OUTPUT_DIR [--epochs N] [--schemes LIST] [--samples LIST] [--jobs N] [--rom-cfl X]
#                      [--dx X]
#                      [-- romp options]
#
# EXPERIMENT
#   gravity-samples   Fig. 11: the gravity cylinder (r = 4), error against the number of sample points
#                     per substep (1, 2, 5, 10, 20, 50, 100, all); the paper: < 1 % from 10 points
#   gravity-manifold  Fig. 21's comparison on the gravity cylinder (the paper's is on the tower): the
#                     nonlinear map against the linear manifold at the same r = 4, 10 and all points
#   torsion           Table 3: torsion-tension (r = 7), 50 and all sample points, on particle domains
#                     (scenes/rom/torsion_tension.toml: the paper's v, stretched to 4 times the length);
#                     the reduced step consistent with these data is --schemes domains-position,domains-velocity
#   torsion-plain     Table 3 on plain material points, the reduced step's discretisation, at v scaled
#                     by 1/20 (scenes/rom/torsion_tension_plain.toml says why)
#   super-resolution  Table 4: the torsion map run at the paper's resolution and written at a sampling
#                     twice as fine (romp run --output-points), against a full-order run at that
#                     resolution; beside it the tracer-particle baseline (the fine points carried by
#                     the coarse full-order run's grid velocity, and held by its particle domains);
#                     50 and all sample points
#   super-resolution-plain
#                     Table 4 on torsion-plain's data and map
#   poke              Table 5: poke-and-recover (r = 6, trained on 12 single pokes, tested on the
#                     other 24 azimuths), 50 and all sample points
#   continual-poking  Table 6: the poke map runs ten pokes in a row (30 s, never seen in training),
#                     against a full-order run of the same sequence; 50 and all sample points
#   tower             Sec. 5.4, Fig. 20: the tower (r = 6) at cell size --dx (default the scene's
#                     0.0192 m, about 45 thousand points; the paper's 0.0048 m is 3 million), 10 and 50
#                     sample points; then the wall seconds per simulated second of the test members'
#                     full-order runs (from the sweep) and reduced runs, and the speed-up
# --epochs N: training length of each map (default 80, short of convergence on a CPU);
# --schemes: comma-separated among lagrangian-position, lagrangian-velocity, eulerian-position,
# eulerian-velocity (default: all four; quadrature, then projection), and domains-position, domains-velocity
# (the reduced step through the particle domains' corners, for the experiments on particle-domain data:
# torsion, super-resolution); --samples: comma-separated sample
# counts, 0 for all points, in place of the experiment's rows; --jobs N: reduced runs of one table cell
# at once (default 1; with N > 1 each on one thread unless the options set --threads); --rom-cfl X: the reduced runs'
# substeps at CFL number X instead of the scene's (romp run --rom-cfl; their files are tagged -cflX);
# --dx X: the tower's cell size in m (a divisor of 0.192, e.g. 0.024, 0.0192, 0.0096, 0.0048);
# options after -- go to every romp command (e.g. -- --device cpu --threads 1).
#
# Exit status: 0 when every run succeeded, 1 when a reduced run (or a tracer baseline) failed (the table
# says which cells, stderr lists their logs), 2 for bad arguments, 130 when interrupted.
#
# Steps whose output exists are skipped and an interrupted training resumes from its checkpoint, so
# experiments on the same OUTPUT_DIR share sweeps and maps; an existing sweep placed at
# OUTPUT_DIR/<scene>/sweep or a map at OUTPUT_DIR/<scene>/<map>.h5 is reused the same way.
set -euo pipefail
# Ctrl-C (or SIGTERM) stops the whole pipeline, not only the run under way: romp finishes its frame and
# exits 130 itself, which bash takes as handled and would go on from; the trap runs once that run has ended.
trap 'echo "interrupted" >&2; exit 130' INT TERM
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
romp="${ROMP:-$root/build/romp}"
usage() { sed -n '7,48p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//' >&2; exit 2; }
[ $# -ge 2 ] || usage
experiment="$1" out="$2"
shift 2
epochs=80 schemes="lagrangian-position,lagrangian-velocity,eulerian-position,eulerian-velocity" sample_rows="" jobs=1
rom_cfl="" tower_dx=0.0192
while [ $# -gt 0 ]; do
  case "$1" in
    --epochs) epochs="$2"; shift 2 ;;
    --schemes) schemes="$2"; shift 2 ;;
    --samples) sample_rows="$2"; shift 2 ;;
    --jobs) jobs="$2"; shift 2 ;;
    --rom-cfl) rom_cfl="$2"; shift 2 ;;
    --dx) tower_dx="$2"; shift 2 ;;
    --) shift; break ;;
    *) usage ;;
  esac
done
options=("$@")
# Processes that share the cores (the sweep's two members, --jobs > 1) run on one thread each unless the
# options set --threads: a one-thread scatter needs no atomics.
shared_cores=(--threads 1)
for option in "${options[@]}"; do [ "$option" != --threads ] || shared_cores=(); done
IFS=, read -r -a scheme_list <<< "$schemes"

# sweep_complete SWEEP: whether every member in SWEEP's manifest has its snapshot. `romp sweep` writes the
# manifest before any member runs, so an interrupted sweep has one too; run again, it resumes the rest.
sweep_complete() {
  [ -f "$1/manifest.json" ] && /usr/bin/python3 - "$1/manifest.json" <<'EOF2'
import json, os, sys
manifest = json.load(open(sys.argv[1]))
folder = os.path.dirname(sys.argv[1])
sys.exit(0 if all(os.path.isfile(os.path.join(folder, m["snapshot"])) for m in manifest["members"]) else 1)
EOF2
}

# sweep NAME SCENE SED: the sweep of scenes/rom/SCENE with the paper's resolution (SED rewrites the
# scene's dx line) in OUTPUT_DIR/NAME/sweep, unless complete there; two members at a time.
sweep() {
  local folder="$out/$1"
  mkdir -p "$folder"
  local scene="$folder/$(basename "$2" .toml)_paper.toml"
  [ -f "$scene" ] || sed "$3" "$root/scenes/rom/$2" > "$scene"
  step 1 "sweep $folder/sweep"
  if ! sweep_complete "$folder/sweep"; then
    "$romp" "${shared_cores[@]}" "${options[@]}" sweep "$scene" -o "$folder/sweep" -j 2 > "$folder/sweep.log" 2>&1
  fi
}

# train MODEL SWEEP [train-rom options]: trains the map unless MODEL exists, resuming a checkpoint.
train() {
  local model="$1" sweep_folder="$2"
  shift 2
  step 2 "training $model"
  [ -f "$model" ] && return 0
  local resume=()
  [ -f "$model.checkpoint" ] && resume=(--resume)
  echo "training: $model ($epochs epochs; its log ${model%.h5}.log says each epoch's ETA)" >&2
  "$romp" "${options[@]}" train-rom "$sweep_folder" -o "$model" --epochs "$epochs" --report-every 20 \
    "${resume[@]}" "$@" > "${model%.h5}.log" 2>&1
}

# test_members SWEEP: one "index scene snapshot name=value,..." line per test member.
test_members() {
  /usr/bin/python3 - "$1/manifest.json" <<'EOF2'
import json, os, sys
manifest = json.load(open(sys.argv[1]))
folder = os.path.dirname(sys.argv[1])
for member in manifest["members"]:
    if member["split"] == "test":
        values = ",".join(f"{name}={value!r}" for name, value in member["values"].items())
        print(member["index"], os.path.join(folder, member["scene"]), os.path.join(folder, member["snapshot"]), values)
EOF2
}

# members_file SWEEP: writes the test members' lines to SWEEP/test_members.txt and prints its path.
members_file() {
  test_members "$1" > "$1/test_members.txt"
  echo "$1/test_members.txt"
}

# error RUN REFERENCE: the accumulated position error (%) of RUN against REFERENCE.
error() {
  "$romp" "${options[@]}" compare "$1" "$2" | sed -n 's/.*accumulated position error \([^%]*\)%.*/\1/p'
}

# rom_run_path MODEL SCHEME SAMPLES INDEX: where the member's reduced run goes.
rom_run_path() {
  echo "$(dirname "$1")/runs/$(basename "$1" .h5)-$2-s$3-m$4${rom_cfl:+-cfl$rom_cfl}.h5"
}

# Overall progress. Each step says "step k/3" (sweep, training, reduced runs) on stderr; the reduced runs
# of a table are planned first (plan_runs N) and each one ended or skipped appends a line to a ledger
# and prints "k/N done, ETA". Runs in parallel (--jobs) append whole short lines (O_APPEND), so the
# counts stay exact.
ledger="$out/.reduced_runs"
# Runs that failed in this call (their logs), so that the script ends with 1 when any did.
failures="$out/.failed_runs"
mkdir -p "$out"
rm -f "$failures"
step() { echo "step $1/3: $2" >&2; }
plan_runs() {
  mkdir -p "$out"
  echo "planned $1 $(date +%s)" > "$ledger"
  step 3 "reduced runs and comparisons ($1 runs)"
}
# ran_run ran|skipped: records one run and prints the progress; the ETA counts the runs made in this
# call only (a skipped one took no time).
ran_run() {
  [ -f "$ledger" ] || return 0
  echo "$1" >> "$ledger"
  awk -v now="$(date +%s)" '
    NR == 1 { planned = $2; start = $3; next }
    { done++ } $1 == "ran" { ran++ }
    END {
      elapsed = now - start
      line = sprintf("reduced runs: %d/%d done (%d were already there), %d s so far", done, planned, done - ran, elapsed)
      if (ran > 0 && done < planned) line = line sprintf(", about %d s left", elapsed / ran * (planned - done))
      print line
    }' "$ledger" >&2
}

# rom_run MODEL SCHEME SAMPLES INDEX SCENE: runs the member reduced unless done; a failed run leaves
# RUN.failed beside its log.
rom_run() {
  local model="$1" quadrature="${2%-*}" projection="${2#*-}" samples="$3" scene="$5"
  local run
  run="$(rom_run_path "$1" "$2" "$3" "$4")"
  mkdir -p "$(dirname "$run")"
  if [ -f "$run" ] && [ ! -f "$run.failed" ]; then ran_run skipped; return 0; fi
  rm -f "$run.failed"
  local threads=()
  [ "$jobs" -le 1 ] || threads=("${shared_cores[@]}")
  "$romp" "${threads[@]}" "${options[@]}" run --no-progress "$scene" --rom "$model" --quadrature "$quadrature" \
    --projection "$projection" --samples "$samples" ${rom_cfl:+--rom-cfl "$rom_cfl"} -o "$run" \
    > "${run%.h5}.log" 2>&1 < /dev/null || { touch "$run.failed"; echo "${run%.h5}.log" >> "$failures"; }
  ran_run ran
}

# summary VALUES...: "mean % (worst %)", or how many runs failed.
summary() {
  /usr/bin/python3 -c '
import sys
values = sys.argv[1:]
bad = sum(v in ("failed", "") for v in values)
if bad:
    print(f"{bad} of {len(values)} runs failed")
else:
    numbers = [float(v) for v in values]
    print(f"{sum(numbers) / len(numbers):.3g} % ({max(numbers):.3g} %)")' "$@"
}

# cell MODEL MEMBERS SCHEME SAMPLES: "mean % (worst %)" over the members listed in the file MEMBERS
# ("index scene reference ..." lines), --jobs of them run at once.
cell() {
  local index scene reference running=0
  while read -r index scene reference _; do
    if [ "$running" -ge "$jobs" ]; then wait -n || true; running=$((running - 1)); fi
    rom_run "$1" "$3" "$4" "$index" "$scene" &
    running=$((running + 1))
  done < "$2"
  wait
  local values=() run
  while read -r index scene reference _; do
    run="$(rom_run_path "$1" "$3" "$4" "$index")"
    values+=("$([ -f "$run" ] && [ ! -f "$run.failed" ] && error "$run" "$reference" || echo failed)")
  done < "$2"
  summary "${values[@]}"
}

# table MODEL MEMBERS LABEL COUNTS...: one row per sample count (0: all), one column per scheme, over
# the members listed in the file MEMBERS; --samples replaces COUNTS.
table() {
  local model="$1" members="$2" label="$3"
  shift 3
  if [ -n "$sample_rows" ]; then
    local counts
    IFS=, read -r -a counts <<< "$sample_rows"
    set -- "${counts[@]}"
  fi
  plan_runs $(($(wc -l < "$members") * ${#scheme_list[@]} * $#))
  local header="| $label | sample points |" rule="|---|---|"
  for scheme in "${scheme_list[@]}"; do header+=" $scheme |"; rule+="---|"; done
  echo "$header"
  echo "$rule"
  local samples
  for samples in "$@"; do
    local row="| $(basename "$model" .h5) | $([ "$samples" = 0 ] && echo all || echo "$samples") |"
    for scheme in "${scheme_list[@]}"; do row+=" $(cell "$model" "$members" "$scheme" "$samples") |"; done
    echo "$row"
  done
}

# superres_table MODEL SWEEP SCENE COUNTS...: Table 4. For each test member: the full-order run of
# scenes/rom/SCENE at its own (finer) resolution with the member's values, the tracer baseline and the
# reduced runs of the member written at the fine run's points, each compared with the fine run. The
# baseline is the paper's, the fine points carried by the coarse run's grid velocity (--tracers-by grid);
# a scene with particle domains also gets the points held by the coarse run's domains (--tracers-by material).
superres_table() {
  local model="$1" sweep_folder="$2" scene="$3"
  shift 3
  local folder="$(dirname "$model")/superres"
  mkdir -p "$folder"
  local index member_scene snapshot values samples carrier carriers=(grid)
  grep -q '^domains = true' "$root/scenes/rom/$scene" && carriers+=(material)
  declare -A cells
  plan_runs $(($(test_members "$sweep_folder" | wc -l) * ${#scheme_list[@]} * $#))
  while read -r index member_scene snapshot values; do
    local fine="$folder/fine-m$index.h5" sets=() assignments
    IFS=, read -r -a assignments <<< "$values"
    for assignment in "${assignments[@]}"; do sets+=(--set "$assignment"); done
    if [ ! -f "$fine" ]; then
      echo "fine full-order run: $fine" >&2
      "$romp" "${options[@]}" run --no-progress "$root/scenes/rom/$scene" "${sets[@]}" -o "$fine" \
        > "${fine%.h5}.log" 2>&1 || { echo "failed: $fine (see ${fine%.h5}.log)" >&2; exit 1; }
    fi
    for carrier in "${carriers[@]}"; do
      local tracers="$folder/tracers-$carrier-m$index.h5"
      [ -f "$tracers" ] || "$romp" "${options[@]}" run --no-progress "$member_scene" --output-points "$fine" \
        --tracers-by "$carrier" -o "$tracers" > "${tracers%.h5}.log" 2>&1 || echo "${tracers%.h5}.log" >> "$failures"
      cells[baseline-$carrier]+=" $([ -f "$tracers" ] && error "$tracers" "$fine" || echo failed)"
    done
    for scheme in "${scheme_list[@]}"; do
      for samples in "$@"; do
        local run="$folder/$(basename "$model" .h5)-$scheme-s$samples-m$index${rom_cfl:+-cfl$rom_cfl}.h5"
        if [ -f "$run" ]; then
          ran_run skipped
        else
          "$romp" "${options[@]}" run --no-progress "$member_scene" --rom "$model" \
            --quadrature "${scheme%-*}" --projection "${scheme#*-}" --samples "$samples" --output-points "$fine" \
            ${rom_cfl:+--rom-cfl "$rom_cfl"} -o "$run" > "${run%.h5}.log" 2>&1 || echo "${run%.h5}.log" >> "$failures"
          ran_run ran
        fi
        cells[$scheme-$samples]+=" $([ -f "$run" ] && error "$run" "$fine" || echo failed)"
      done
    done
  done < <(test_members "$sweep_folder")
  echo "| scheme | sample points | position error against the fine full-order run |"
  echo "|---|---|---|"
  for scheme in "${scheme_list[@]}"; do
    for samples in "$@"; do
      # shellcheck disable=SC2086  # a cell is a list of numbers
      echo "| $scheme | $([ "$samples" = 0 ] && echo all || echo "$samples") | $(summary ${cells[$scheme-$samples]}) |"
    done
  done
  # shellcheck disable=SC2086
  echo "| tracer-particle baseline (the fine points carried by the coarse run's grid) | - | $(summary ${cells[baseline-grid]}) |"
  # shellcheck disable=SC2086
  [ -z "${cells[baseline-material]:-}" ] ||
    echo "| the fine points held by the coarse run's particle domains | - | $(summary ${cells[baseline-material]}) |"
}

# wall_per_second LOG: wall seconds per simulated second of the run that wrote LOG (romp run's summary).
wall_per_second() {
  sed -n 's/.*substeps (\([0-9.e+-]*\) s simulated) in \([0-9.]*\) s on.*/\2 \1/p' "$1" | awk '{ printf "%.4g\n", $1 / $2 }'
}

# median VALUES...: their median, or "-" if there are none.
median() {
  [ $# -gt 0 ] || { echo -; return; }
  printf '%s\n' "$@" | sort -g | awk '{ v[NR] = $1 } END { printf "%.3g\n", NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'
}

# speed_table MODEL SWEEP MEMBERS COUNTS...: over the test members, the median wall seconds per simulated
# second of the full-order runs (the sweep's logs) and of each scheme's reduced runs, and the speed-up.
# Like with like: the sweep runs two members at a time, one thread each, and so do the reduced runs
# with --jobs 2.
speed_table() {
  local model="$1" sweep_folder="$2" members="$3" index scene reference log full=() values
  shift 3
  local count value
  count="$(wc -l < "$members")"
  while read -r index scene reference _; do
    log="$sweep_folder/logs/$(basename "$reference" .h5).log"
    value="$([ -f "$log" ] && wall_per_second "$log")" || true
    [ -z "$value" ] || full+=("$value")
  done < "$members"
  local full_median
  full_median="$(median "${full[@]}")"
  echo "| run | sample points | wall s per simulated s (median over test members) | members timed | speed-up over full order |"
  echo "|---|---|---|---|---|"
  echo "| full order | - | $full_median | ${#full[@]} of $count | 1 |"
  for scheme in "${scheme_list[@]}"; do
    for samples in "$@"; do
      values=()
      while read -r index scene reference _; do
        log="$(rom_run_path "$model" "$scheme" "$samples" "$index")"
        # A run that stopped (RUN.failed) or did not finish has no summary line.
        value="$([ -f "${log%.h5}.log" ] && [ ! -f "$log.failed" ] && wall_per_second "${log%.h5}.log")" || true
        [ -z "$value" ] || values+=("$value")
      done < "$members"
      local rom_median
      rom_median="$(median "${values[@]}")"
      echo "| $scheme | $samples | $rom_median | ${#values[@]} of $count | $(awk -v f="$full_median" -v r="$rom_median" 'BEGIN { if (r + 0 > 0 && f + 0 > 0) printf "%.3g", f / r; else print "-" }') |"
    done
  done
}

case "$experiment" in
  gravity-samples)
    sweep gravity gravity_cylinder.toml 's/^dx = 0.002 .*/dx = 0.004/'
    train "$out/gravity/mlp_r4.h5" "$out/gravity/sweep" --latent 4
    table "$out/gravity/mlp_r4.h5" "$(members_file "$out/gravity/sweep")" map 1 2 5 10 20 50 100 0
    ;;
  gravity-manifold)
    sweep gravity gravity_cylinder.toml 's/^dx = 0.002 .*/dx = 0.004/'
    train "$out/gravity/mlp_r4.h5" "$out/gravity/sweep" --latent 4
    train "$out/gravity/linear_r4.h5" "$out/gravity/sweep" --latent 4 --linear
    members="$(members_file "$out/gravity/sweep")"
    table "$out/gravity/mlp_r4.h5" "$members" map 10 0
    table "$out/gravity/linear_r4.h5" "$members" map 10 0 | tail -n +3
    ;;
  torsion | torsion-plain)
    name="$experiment" scene="torsion_tension${experiment#torsion}.toml"
    scene="${scene/-/_}"
    sweep "$name" "$scene" 's/^dx = 0.00125 .*/dx = 0.0025/'
    train "$out/$name/mlp_r7.h5" "$out/$name/sweep" --latent 7
    table "$out/$name/mlp_r7.h5" "$(members_file "$out/$name/sweep")" map 50 0
    ;;
  super-resolution | super-resolution-plain)
    name="torsion${experiment#super-resolution}" scene="torsion_tension${experiment#super-resolution}.toml"
    scene="${scene/-/_}"
    sweep "$name" "$scene" 's/^dx = 0.00125 .*/dx = 0.0025/'
    train "$out/$name/mlp_r7.h5" "$out/$name/sweep" --latent 7
    counts=(50 0)
    [ -z "$sample_rows" ] || IFS=, read -r -a counts <<< "$sample_rows"
    superres_table "$out/$name/mlp_r7.h5" "$out/$name/sweep" "$scene" "${counts[@]}"
    ;;
  poke)
    sweep poke poke_recover.toml ''
    train "$out/poke/mlp_r6.h5" "$out/poke/sweep" --latent 6
    table "$out/poke/mlp_r6.h5" "$(members_file "$out/poke/sweep")" map 50 0
    ;;
  continual-poking)
    sweep poke poke_recover.toml ''
    train "$out/poke/mlp_r6.h5" "$out/poke/sweep" --latent 6
    reference="$out/poke/continual/full.h5"
    mkdir -p "$out/poke/continual"
    if [ ! -f "$reference" ]; then
      echo "full-order run: $reference" >&2
      "$romp" "${options[@]}" run --no-progress "$root/scenes/rom/continual_poking.toml" -o "$reference" \
        > "${reference%.h5}.log" 2>&1 || { echo "failed: $reference (see ${reference%.h5}.log)" >&2; exit 1; }
    fi
    echo "continual $root/scenes/rom/continual_poking.toml $reference -" > "$out/poke/continual/members.txt"
    table "$out/poke/mlp_r6.h5" "$out/poke/continual/members.txt" map 50 0
    ;;
  tower)
    folder="$out/tower-dx$tower_dx"
    sweep "tower-dx$tower_dx" tower.toml "s/^dx = 0.0192 .*/dx = $tower_dx/"
    train "$folder/mlp_r6.h5" "$folder/sweep" --latent 6
    members="$(members_file "$folder/sweep")"
    table "$folder/mlp_r6.h5" "$members" map 10 50
    counts=(10 50)
    [ -z "$sample_rows" ] || IFS=, read -r -a counts <<< "$sample_rows"
    speed_table "$folder/mlp_r6.h5" "$folder/sweep" "$members" "${counts[@]}"
    ;;
  *) usage ;;
esac
# The table says how many runs of a cell failed; the exit status says whether any did.
if [ -s "$failures" ]; then
  echo "$(wc -l < "$failures") reduced run(s) failed; their logs:" >&2
  sed 's/^/  /' "$failures" >&2
  exit 1
fi
