#!/usr/bin/env bash
# Evaluates a learned law on the neural-law paper's generalisation tasks (Ma et al. 2023, Sec. 4.3):
# each scene of scenes/nclaw/generalization for MATERIAL runs twice, with the analytic ground-truth
# material and with the law in its place (`romp run --law`), and `romp compare` gives the paper's
# metric, the mean position MSE over the frames after the first (the scenes write every 5th substep).
#
#   tools/nclaw_evaluate.sh MATERIAL LAW.h5 OUTPUT_DIR [romp options, e.g. --device cpu]
#
# MATERIAL is jelly, sand, plasticine or water. The ground-truth runs go to OUTPUT_DIR/truth/MATERIAL and are
# reused by later evaluations of that material into the same folder (they were once keyed by task alone, so a
# second material's laws were compared with the first material's ground truth); the law's runs go to
# OUTPUT_DIR/<law file stem>.
# Prints one markdown row per task: (a) long, (b) velocities (the mean over the sweep's three members),
# (c) shape, (d) inclined; a learned run that stops non-finite is reported as such, not as a number.
set -uo pipefail
# Ctrl-C (or SIGTERM) stops the whole evaluation, not only the run under way: romp finishes its frame and
# exits 130 itself, which bash takes as handled and would go on from; the trap runs once that run has ended.
trap 'echo "interrupted" >&2; exit 130' INT TERM
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
romp="${ROMP:-$root/build/romp}"
material="$1"
law="$(realpath "$2")"
out="$3"
shift 3
options=("$@")
scenes="$root/scenes/nclaw/generalization"
truth_dir="$out/truth/$material"
learned_dir="$out/$(basename "$law" .h5)"
mkdir -p "$truth_dir" "$learned_dir"

# mean_mse RUN REFERENCE: the mean MSE romp compare prints, or nothing.
mean_mse() {
  "$romp" "${options[@]}" compare "$1" "$2" | sed -n 's/.*over frames after the first \([^ ]*\) m^2.*/\1/p'
}

# run_once SCENE OUTPUT [--law ...]: runs unless OUTPUT exists; returns romp's exit code.
run_once() {
  local scene="$1" output="$2"
  shift 2
  [ -f "$output" ] && return 0
  "$romp" "${options[@]}" run --no-progress "$scene" -o "$output" "$@" > "${output%.h5}.log" 2>&1
}

echo "| task | scene | mean position MSE (m^2) |"
echo "|---|---|---|"
for task in long shape inclined; do
  scene="$scenes/${task}_${material}.toml"
  truth="$truth_dir/$task.h5" learned="$learned_dir/$task.h5"
  if ! run_once "$scene" "$truth"; then
    echo "| $task | ${task}_${material}.toml | ground truth failed: see ${truth%.h5}.log |"
    continue
  fi
  if run_once "$scene" "$learned" --law "$material=$law"; then
    echo "| $task | ${task}_${material}.toml | $(mean_mse "$learned" "$truth") |"
  else
    echo "| $task | ${task}_${material}.toml | learned run stopped: $(grep -o 'non-finite.*' "${learned%.h5}.log" | head -1) |"
  fi
done

scene="$scenes/velocities_${material}.toml"
"$romp" "${options[@]}" sweep "$scene" -o "$truth_dir/velocities" > "$truth_dir/velocities.log" 2>&1
"$romp" "${options[@]}" sweep "$scene" -o "$learned_dir/velocities" --law "$material=$law" \
  > "$learned_dir/velocities.log" 2>&1
values=()
for truth in "$truth_dir"/velocities/member_*.h5; do
  learned="$learned_dir/velocities/$(basename "$truth")"
  if [ -f "$learned" ]; then values+=("$(mean_mse "$learned" "$truth")"); else values+=("failed"); fi
done
if [[ " ${values[*]} " == *" failed "* ]] || [ "${#values[@]}" -eq 0 ]; then
  echo "| velocities | velocities_${material}.toml | members: ${values[*]:-none} (see $learned_dir/velocities/logs) |"
else
  mean="$(printf '%s\n' "${values[@]}" | awk '{ s += $1 } END { printf "%.3g", s / NR }')"
  echo "| velocities | velocities_${material}.toml (mean of ${#values[@]}: ${values[*]}) | $mean |"
fi
