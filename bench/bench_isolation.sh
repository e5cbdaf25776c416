#!/usr/bin/env bash
# The cost of reading HDF5 metadata in a child process first (io/isolation.hpp,
# docs/reliability.md "Damaged and hostile HDF5 files"): a lot of UNITS small six-channel units
# (the demo model, SECONDS each at 1 kHz) is analysed by two binaries side by side, OLD (built
# without the isolation) and NEW, in alternation RUNS times each, and its results, their seals
# removed as results of earlier versions have none, are summarized by both: the one case where
# `summarize` starts a child per results file. Prints a Markdown table of the medians and writes
# JSON (bench/results/bench_isolation.json unless --json names another file).
#
#   bench/bench_isolation.sh --old OLD_BINARY [--new build/allanlot] [--units 200]
#                            [--duration 10] [--runs 5] [--threads 1] [--workdir DIR]
#                            [--json FILE]
#
# Wall time and CPU time (user + system, the children's included) from GNU time; on shared cores
# the wall time also holds the waits for a core at each hand-over between parent and child, the
# CPU time is the work. --force makes every run analyse every unit.
set -euo pipefail
cd "$(dirname "$0")/.."

old=""
new="build/allanlot"
units=200
duration=10
runs=5
threads=1
workdir="${TMPDIR:-/tmp}/allanlot-bench-isolation"
json="bench/results/bench_isolation.json"
while [ $# -gt 0 ]; do
  case "$1" in
    --old) old="$2"; shift 2 ;;
    --new) new="$2"; shift 2 ;;
    --units) units="$2"; shift 2 ;;
    --duration) duration="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --threads) threads="$2"; shift 2 ;;
    --workdir) workdir="$2"; shift 2 ;;
    --json) json="$2"; shift 2 ;;
    *) echo "bench_isolation: unknown option $1" >&2; exit 2 ;;
  esac
done
[ -x "$old" ] || { echo "bench_isolation: --old BINARY (built without the isolation) needed" >&2; exit 2; }
[ -x "$new" ] || { echo "bench_isolation: no binary at $new" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "bench_isolation: needs GNU time (apt-get install time)" >&2; exit 2; }

lot="$workdir/lot-$units-$duration"
if [ ! -f "$lot/manifest.txt" ]; then
  mkdir -p "$workdir"
  "$new" simulate --lot "$units" --duration "$duration" --seed 2026 -o "$lot" --quiet
fi

# "wall cpu" seconds of one command.
timed() {
  local stats="$workdir/time.txt"
  /usr/bin/time -f "%e %U %S" -o "$stats" "$@" >/dev/null 2>&1 || true
  awk '{ printf "%s %.2f", $1, $2 + $3 }' "$stats"
}

median() {
  tr ' ' '\n' | sed '/^$/d' | sort -g | awk '{ v[NR] = $1 } END {
    if (NR % 2) print v[(NR + 1) / 2]; else printf "%.3f\n", (v[NR / 2] + v[NR / 2 + 1]) / 2 }'
}

declare -A times cpus
for _ in $(seq "$runs"); do
  for which in old new; do
    bin="$old"
    [ "$which" = new ] && bin="$new"
    out="$workdir/out-$which"
    rm -rf "$out"
    read -r wall cpu <<<"$(timed "$bin" analyze --force --quiet --threads "$threads" -o "$out" "@$lot/manifest.txt")"
    times[analyze_$which]+=" $wall"
    cpus[analyze_$which]+=" $cpu"
    # Results of an earlier version: no seal (the HDF5 image without its 512-byte user block).
    for f in "$out"/*.allan.h5; do
      tail -c +513 "$f" >"$f.unsealed" && mv "$f.unsealed" "$f"
    done
    read -r wall cpu <<<"$(timed "$bin" summarize --quiet "$out")"
    times[summarize_$which]+=" $wall"
    cpus[summarize_$which]+=" $cpu"
  done
done

mkdir -p "$(dirname "$json")"
echo "| command ($units units of $duration s, $runs runs) | old wall s | new wall s | wall per unit ms | old CPU s | new CPU s | CPU per unit ms |"
echo "|---|---|---|---|---|---|---|"
entries=()
for cmd in analyze summarize; do
  o=$(echo "${times[${cmd}_old]}" | median)
  n=$(echo "${times[${cmd}_new]}" | median)
  per=$(awk -v o="$o" -v n="$n" -v u="$units" 'BEGIN { printf "%.2f", (n - o) * 1000 / u }')
  oc=$(echo "${cpus[${cmd}_old]}" | median)
  nc=$(echo "${cpus[${cmd}_new]}" | median)
  per_cpu=$(awk -v o="$oc" -v n="$nc" -v u="$units" 'BEGIN { printf "%.2f", (n - o) * 1000 / u }')
  echo "| $cmd | $o | $n | $per | $oc | $nc | $per_cpu |"
  old_list=$(echo "${times[${cmd}_old]}" | xargs | tr ' ' ',')
  new_list=$(echo "${times[${cmd}_new]}" | xargs | tr ' ' ',')
  entries+=("{\"command\": \"$cmd\", \"units\": $units, \"duration_s\": $duration, \"runs\": $runs, \"old_s\": [$old_list], \"new_s\": [$new_list], \"old_median_s\": $o, \"new_median_s\": $n, \"per_unit_ms\": $per, \"old_cpu_median_s\": $oc, \"new_cpu_median_s\": $nc, \"cpu_per_unit_ms\": $per_cpu}")
done
{
  echo "["
  for i in "${!entries[@]}"; do
    sep=","
    [ "$i" -eq $((${#entries[@]} - 1)) ] && sep=""
    echo "  ${entries[$i]}$sep"
  done
  echo "]"
} >"$json"
echo "wrote $json"
