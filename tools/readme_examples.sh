#!/usr/bin/env bash
# Runs the example block of README.md (the ```sh block under "## Running") line by line, in order, the
# way a reader would after the quick start's build: each line from a scratch folder that holds links to
# the repository's build/, scenes/ and tools/ (so every runs/... and romp-bench-results/ the block writes
# lands there and the repository's runs/ is untouched). Backslash-continued lines are joined. Every
# line must exit 0; the first that does not stops the test, which names it, prints the end of its log
# and keeps the scratch folder.
#
#   tools/readme_examples.sh [--dry-run] [--as-written] [--keep] [--build DIR] [--readme FILE]
#
#   --dry-run     print each line as it would run (after the rewrites below) and what is skipped; run nothing
#   --as-written  no rewrites: every line exactly as the README has it (hours on a CPU: the neural-law
#                 training alone is 300 epochs of 1000-substep rollouts)
#   --keep        keep the scratch folder also when every line passed
#   --build DIR   the build folder to link as build/ (default: the repository's build/)
#   --readme FILE the README to read (default: the repository's README.md)
#
# A line whose trailing comment says "(not run by the test: REASON)" is printed and skipped. Keep such
# lines to the minimum: lines that cannot run on one machine.
#
# Shortening. With the rewrites below the whole block took 5 to 8 minutes on 2 CPU cores shared with other builds.
# Each is applied to a line that matches its pattern (several can apply to one line):
#
# | pattern                              | added options / action                     | why
# |--------------------------------------|--------------------------------------------|------------------------------------------
# | romp learn-law                       | --epochs 1 --steps 5                       | the paper's protocol (300 epochs of 1000-substep rollouts) takes hours on a CPU
# | --law NAME=runs/...                  | --law NAME=scenes/nclaw/laws/NAME.h5       | a law learned in 1 epoch of 5 substeps is untrained: a run with it goes non-finite (exit 4); the shipped law is the trained one
# | romp train-rom                       | --epochs 2                                 | the default 1000 epochs take hours on a CPU (2, not 1: see --resume)
# | romp run/train-rom ... --resume      | first: the line without --resume, stopped  | the line continues an interrupted run, as its comment says (on a finished one --resume of
# |                                      | by SIGINT (Ctrl-C) once it has started; it | run has nothing to do, and train-rom's exits 3: no checkpoint); the stopped run must print
# |                                      | must exit 130                              | "interrupted after" and exit 130
# | romp run ... --rom M (no --samples)  | --samples 10                               | a reduced run over every point (the default) took 3 times as long on the CPU
# | mpirun                               | --oversubscribe; as root also              | -n 4 on fewer cores is refused without it; CI containers run as root, which Open MPI refuses
# |                                      | OMPI_ALLOW_RUN_AS_ROOT(_CONFIRM)=1         | unless told; skipped when mpirun is not installed (the quick start installs openmpi-bin)
# | tools/rom_paper.sh gravity-*  DIR    | --epochs 2 --schemes lagrangian-position   | the experiment's 8 sample counts x 4 schemes x 6 test members are 192 reduced runs; its own
# |                                      | --samples 10; runs/gravity and             | sweep at dx = 4 mm and map of rank 4 are what the block made already, placed (links) where
# |                                      | runs/gravity_rom.h5 linked as DIR/gravity/ | the script reuses an existing sweep and map
# |                                      | sweep and DIR/gravity/mlp_r4.h5            |
# | tools/nclaw_evaluate.sh              | skipped (its law argument must exist)      | no option shortens it: its shape and inclined tasks (27 thousand particles; Spot on a 128^3
# |                                      |                                            | grid) run twice each, tens of minutes on 2 cores
# | romp run jelly_into_water_pool.toml  | romp check with the same scene and --law   | 117 thousand particles for 1 s: tens of minutes on 2 cores; check still loads the scene and the law
# | romp-bench --suite rom               | --rom-samples 10 --threads 2               | 12 reduced cases at 1 and 2 threads: about 6 minutes
# | romp-bench --suite (other suites)    | --scale 0.1, --repeats 1, --warmup 0       | full-size problems, 2 warm-up runs and 10 timed repeats each
# |                                      | (those the line lacks)                     |
# | /usr/bin/python3 tools/plot_rom_bench.py | skipped when /usr/bin/python3 has no   | the quick start does not install python3-matplotlib
# |                                      | matplotlib                                 |
#
# Exit status: 0 every line passed (or was skipped as above), 1 a line failed, 2 bad arguments or no
# block found. ctest runs it as docs.readme_examples.
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
readme="$root/README.md" build="$root/build" dry_run=0 as_written=0 keep=0
usage() { sed -n '9,16p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//' >&2; exit 2; }
while [ $# -gt 0 ]; do
  case "$1" in
    --dry-run) dry_run=1; shift ;;
    --as-written) as_written=1; shift ;;
    --keep) keep=1; shift ;;
    --build) [ $# -ge 2 ] || usage; build="$(cd "$2" && pwd)" || exit 2; shift 2 ;;
    --readme) [ $# -ge 2 ] || usage; readme="$2"; shift 2 ;;
    -h|--help) usage ;;
    *) echo "unknown argument: $1" >&2; usage ;;
  esac
done
[ -f "$readme" ] || { echo "no README at $readme" >&2; exit 2; }

# The block's logical lines: the first ```sh block under "## Running", continuation lines joined.
mapfile -t lines < <(awk '
  /^## / { section = ($0 ~ /^## Running[[:space:]]*$/); next }
  section && !done && /^```sh[[:space:]]*$/ { inside = 1; next }
  inside && /^```/ { inside = 0; done = 1; if (pending != "") print pending; next }
  inside {
    line = $0
    if (pending != "") sub(/^[[:space:]]+/, "", line)
    if (line ~ /\\[[:space:]]*$/) { sub(/[[:space:]]*\\[[:space:]]*$/, "", line); pending = pending line " "; next }
    if (line ~ /^[[:space:]]*$/) next
    print pending line; pending = ""
  }' "$readme")
[ "${#lines[@]}" -gt 0 ] || { echo "no \`\`\`sh block under '## Running' in $readme" >&2; exit 2; }
if [ "$dry_run" -eq 0 ] && [ ! -x "$build/romp" ]; then
  echo "no $build/romp: build first (tools/quickstart.sh or tools/build.sh)" >&2
  exit 2
fi

# shorten LINE: sets cmd (what runs), action (run, skip), reason (why skipped), notes (rewrites applied),
# interrupt (a command to start and stop with SIGINT first, or empty), setup (a command run first) and
# failure (a pattern whose presence in the line's output fails it although it exited 0).
shorten() {
  cmd="$1" action=run reason="" notes=() interrupt="" setup="" failure=""
  [ "$as_written" -eq 1 ] && return
  if [[ "$cmd" =~ (^|[[:space:]])(build/)?romp[[:space:]].*learn-law ]]; then
    cmd+=" --epochs 1 --steps 5"; notes+=("learn-law: --epochs 1 --steps 5")
  fi
  if [[ "$cmd" =~ --law[[:space:]]+([A-Za-z0-9_]+)=runs/[^[:space:]]+ ]]; then
    local name="${BASH_REMATCH[1]}"
    cmd="${cmd/"${BASH_REMATCH[0]}"/--law $name=scenes/nclaw/laws/$name.h5}"
    notes+=("--law $name=scenes/nclaw/laws/$name.h5 (the shortened law is untrained)")
  fi
  if [[ "$cmd" == *" train-rom "* ]]; then
    cmd+=" --epochs 2"; notes+=("train-rom: --epochs 2")
  fi
  if [[ "$cmd" == *" --resume"* && ( "$cmd" == *" run "* || "$cmd" == *" train-rom "* ) ]]; then
    interrupt="${cmd/ --resume/}"
    notes+=("first the same without --resume, stopped by SIGINT")
  fi
  if [[ "$cmd" == *" --rom "* && "$cmd" == *" run "* && "$cmd" != *" --samples "* ]]; then
    cmd+=" --samples 10"; notes+=("reduced run: --samples 10")
  fi
  if [[ "$cmd" =~ ^mpirun[[:space:]] ]]; then
    if ! command -v mpirun > /dev/null; then
      action=skip reason="mpirun is not installed (the quick start installs openmpi-bin)"
    fi
    cmd="mpirun --oversubscribe${cmd#mpirun}"
    [ "$(id -u)" -ne 0 ] || cmd="OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 $cmd"
    notes+=("mpirun --oversubscribe$([ "$(id -u)" -ne 0 ] || echo ', allowed as root')")
  fi
  if [[ "$cmd" =~ tools/rom_paper\.sh[[:space:]]+(gravity-[a-z]+)[[:space:]]+([^[:space:]]+) ]]; then
    local out="${BASH_REMATCH[2]}"
    cmd+=" --epochs 2 --schemes lagrangian-position --samples 10"
    setup="mkdir -p $out/gravity && { [ ! -d runs/gravity ] || ln -sfn \"\$PWD/runs/gravity\" $out/gravity/sweep; } && \
{ [ ! -f runs/gravity_rom.h5 ] || ln -sfn \"\$PWD/runs/gravity_rom.h5\" $out/gravity/mlp_r4.h5; }"
    failure="runs failed"
    notes+=("rom_paper.sh: --epochs 2 --schemes lagrangian-position --samples 10; reuses runs/gravity and runs/gravity_rom.h5")
  fi
  if [[ "$cmd" =~ tools/nclaw_evaluate\.sh[[:space:]]+[^[:space:]]+[[:space:]]+([^[:space:]]+) ]]; then
    action=skip reason="no option shortens it (tens of minutes on 2 cores)"
    setup="test -f ${BASH_REMATCH[1]}"
  fi
  if [[ "$cmd" == *" run "*"jelly_into_water_pool.toml"* ]]; then
    cmd="${cmd/ run / check }"; notes+=("run -> check (117 thousand particles for 1 s)")
  fi
  if [[ "$cmd" == *"romp-bench "*"--suite"* ]]; then
    if [[ "$cmd" == *"--suite rom"* ]]; then
      cmd+=" --rom-samples 10 --threads 2"; notes+=("romp-bench rom: --rom-samples 10 --threads 2")
    else
      local option added=""
      for option in "--scale 0.1" "--repeats 1" "--warmup 0"; do
        [[ "$cmd" == *" ${option% *} "* || "$cmd" == *" ${option% *}" ]] || { cmd+=" $option"; added+=" $option"; }
      done
      notes+=("romp-bench:$added")
    fi
  fi
  if [[ "$cmd" == *"tools/plot_rom_bench.py"* ]] && ! /usr/bin/python3 -c "import matplotlib" 2> /dev/null; then
    action=skip reason="/usr/bin/python3 has no matplotlib (apt-get install python3-matplotlib)"
  fi
}

work=""
if [ "$dry_run" -eq 0 ]; then
  work="$(mktemp -d "${TMPDIR:-/tmp}/romp-readme-examples.XXXXXX")"
  ln -s "$build" "$work/build"
  ln -s "$root/scenes" "$work/scenes"
  ln -s "$root/tools" "$work/tools"
  mkdir -p "$work/logs"
  echo "README examples from $readme: ${#lines[@]} lines, run in $work"
fi
# Ctrl-C stops the test (romp finishes its frame and exits 130, which bash would take as handled).
trap 'echo "interrupted; scratch folder kept: $work" >&2; exit 130' INT TERM

now() { date +%s.%N; }
seconds() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f", b - a }'; }
start_all="$(now)" passed=0 skipped=0 skipped_lines=()
for i in "${!lines[@]}"; do
  line="${lines[$i]}" n=$((i + 1))
  command="${line%%[[:space:]]#*}" comment=""
  [ "$command" = "$line" ] || comment="${line#"$command"}"
  command="${command%"${command##*[![:space:]]}"}"
  printf '\n[%d/%d] %s\n' "$n" "${#lines[@]}" "$command"
  if [[ "$comment" =~ \(not\ run\ by\ the\ test:\ ([^\)]*)\) ]]; then
    echo "      skipped: ${BASH_REMATCH[1]} (marked in the README)"
    skipped=$((skipped + 1)) skipped_lines+=("$n: ${BASH_REMATCH[1]}")
    continue
  fi
  shorten "$command"
  for note in ${notes[@]+"${notes[@]}"}; do echo "      shortened: $note"; done
  [ "$cmd" = "$command" ] || echo "      runs: $cmd"
  [ -z "$interrupt" ] || echo "      first: $interrupt (stopped by SIGINT)"
  if [ "$dry_run" -eq 1 ]; then
    [ "$action" = run ] || echo "      skipped: $reason"
    continue
  fi
  log="$work/logs/$(printf '%02d' "$n").log"
  start="$(now)" status=0
  if [ -n "$setup" ]; then
    (cd "$work" && bash -c "$setup") >> "$log" 2>&1 || status=$?
  fi
  if [ "$action" = skip ]; then
    if [ "$status" -ne 0 ]; then
      echo "      FAILED: its input is missing (skipped otherwise: $reason)"
      echo "FAILED at line $n of the block: $command" >&2
      echo "scratch folder kept: $work" >&2
      exit 1
    fi
    echo "      skipped: $reason"
    skipped=$((skipped + 1)) skipped_lines+=("$n: $reason")
    continue
  fi
  if [ "$status" -eq 0 ] && [ -n "$interrupt" ]; then
    # Start the line without --resume, wait until it works (a frame, or training under way), stop it.
    (cd "$work" && exec bash -c "exec $interrupt") > "$log.interrupted" 2>&1 &
    pid=$!
    for _ in $(seq 1 600); do
      grep -qE 'frame [0-9]+/|training on' "$log.interrupted" 2> /dev/null && break
      kill -0 "$pid" 2> /dev/null || break
      sleep 0.2
    done
    sleep 1
    kill -INT "$pid" 2> /dev/null
    wait "$pid"
    first=$?
    if [ "$first" -ne 130 ] || ! grep -q "interrupted after" "$log.interrupted"; then
      echo "      FAILED: the run to continue, stopped by SIGINT, exited $first (130 and \"interrupted after\" expected)"
      tail -n 15 "$log.interrupted" | sed 's/^/      | /'
      echo "FAILED at line $n of the block: $command" >&2
      echo "scratch folder kept: $work" >&2
      exit 1
    fi
    echo "      stopped after $(seconds "$start" "$(now)") s: $(grep -o 'interrupted after [a-z]* [0-9]*' "$log.interrupted" | head -1)"
  fi
  [ "$status" -ne 0 ] || { (cd "$work" && bash -c "$cmd") >> "$log" 2>&1 || status=$?; }
  if [ "$status" -eq 0 ] && [ -n "$failure" ] && grep -q "$failure" "$log"; then
    echo "      its output says \"$failure\""
    status=1
  fi
  elapsed="$(seconds "$start" "$(now)")"
  if [ "$status" -ne 0 ]; then
    echo "      FAILED: exit $status after $elapsed s; the end of $log:"
    tail -n 20 "$log" | sed 's/^/      | /'
    echo
    echo "FAILED at line $n of the block (exit $status): $command" >&2
    echo "scratch folder kept: $work" >&2
    exit 1
  fi
  echo "      ok, $elapsed s"
  passed=$((passed + 1))
done

echo
if [ "$dry_run" -eq 1 ]; then
  echo "dry run: ${#lines[@]} lines"
  exit 0
fi
echo "README examples: ${#lines[@]} lines, $passed passed, $skipped skipped, in $(seconds "$start_all" "$(now)") s"
for entry in ${skipped_lines[@]+"${skipped_lines[@]}"}; do echo "  skipped line $entry"; done
if [ "$keep" -eq 1 ]; then echo "scratch folder kept: $work"; else rm -rf "$work"; fi
exit 0
