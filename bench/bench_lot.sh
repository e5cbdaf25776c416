#!/usr/bin/env bash
# Whole-lot throughput through the real binary (docs/performance.md "Lots"): simulates a lot
# of UNITS six-channel 1 kHz units of SECONDS each (the embedded demo model; 5400 s, 5.4 M
# samples a channel, by default) once into WORKDIR/lot-UNITS[-SECONDS], then times `allanlot
# analyze` on it at each thread count, with all defaults (six statistics with confidence
# intervals, eq. (3) fit, PSD, PSD fit, cross-check). Prints a Markdown table with the seconds
# per unit and writes JSON (bench/results/bench_lot.json unless --json names another file).
#
#   bench/bench_lot.sh [--units 8] [--duration 5400] [--threads "1 2"] [--workdir DIR]
#                      [--binary build/allanlot] [--json FILE]
#
# Short units measure the per-file overhead (issue 25: --units 200 --duration 60), a lot of
# 30-minute units the units per hour (--units 60 --duration 1800).
#
# Wall time, CPU time and peak RSS come from GNU time (`/usr/bin/time -f`); --force makes every
# run analyse every unit (no resume).
set -euo pipefail
cd "$(dirname "$0")/.."

units=8
duration=5400
json="bench/results/bench_lot.json"
threads="2"
workdir="${TMPDIR:-/tmp}/allanlot-bench-lot"
binary="build/allanlot"
while [ $# -gt 0 ]; do
  case "$1" in
    --units) units="$2"; shift 2 ;;
    --duration) duration="$2"; shift 2 ;;
    --json) json="$2"; shift 2 ;;
    --threads) threads="$2"; shift 2 ;;
    --workdir) workdir="$2"; shift 2 ;;
    --binary) binary="$2"; shift 2 ;;
    *) echo "bench_lot: unknown option $1" >&2; exit 2 ;;
  esac
done
[ -x "$binary" ] || { echo "bench_lot: no binary at $binary (build the release preset)" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "bench_lot: needs GNU time (apt-get install time)" >&2; exit 2; }

lot="$workdir/lot-$units"
[ "$duration" = 5400 ] || lot="$lot-$duration"
if [ ! -f "$lot/manifest.txt" ]; then
  mkdir -p "$workdir"
  "$binary" simulate --lot "$units" --duration "$duration" --seed 2026 -o "$lot" --quiet
fi
samples=$((units * 6 * duration * 1000))

mkdir -p "$(dirname "$json")"
echo "| threads | units | wall | s/unit | units/hour | samples/s | CPU | peak RSS |"
echo "|---|---|---|---|---|---|---|---|"
entries=()
for t in $threads; do
  out="$workdir/out-$t"
  rm -rf "$out"
  stats="$workdir/time-$t.txt"
  /usr/bin/time -f "%e %U %S %M" -o "$stats" \
    "$binary" analyze --force --quiet --threads "$t" -o "$out" "@$lot/manifest.txt"
  read -r wall user sys rss_kb <"$stats"
  cpu=$(awk -v u="$user" -v s="$sys" 'BEGIN { printf "%.1f", u + s }')
  per_hour=$(awk -v n="$units" -v w="$wall" 'BEGIN { printf "%.0f", n * 3600 / w }')
  rate=$(awk -v n="$samples" -v w="$wall" 'BEGIN { printf "%.2f", n / w / 1e6 }')
  per_unit=$(awk -v n="$units" -v w="$wall" 'BEGIN { printf "%.3f", w / n }')
  rss_mb=$((rss_kb / 1024))
  echo "| $t | $units | ${wall} s | $per_unit s | $per_hour | ${rate} M | ${cpu} s | ${rss_mb} MB |"
  entries+=("{\"threads\": $t, \"units\": $units, \"wall_s\": $wall, \"s_per_unit\": $per_unit, \"cpu_s\": $cpu, \"units_per_hour\": $per_hour, \"samples_per_s\": $(awk -v r="$rate" 'BEGIN { print r * 1e6 }'), \"peak_rss_mb\": $rss_mb}")
done
{
  echo "{\"benchmark\": \"bench_lot\", \"date\": \"$(date -u +%Y-%m-%dT%H:%M:%SZ)\", \"host\": \"$(hostname)\", \"nproc\": $(nproc), \"unit_seconds\": $duration, \"samples_per_unit\": $((6 * duration * 1000)), \"runs\": ["
  (IFS=,; echo "${entries[*]}")
  echo "]}"
} >"$json"
echo "wrote $json"
