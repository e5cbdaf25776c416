#!/usr/bin/env bash
# Wall time of `allanlot analyze` on one recording given as an argument (a real unit, whose
# licence keeps it out of the repository, or a simulated one), with every default:
#   allanlot analyze --force --quiet --threads T -o OUT FILE
# run RUNS times; with --old OLD_BINARY the two binaries alternate (new, old, new, old ...) so
# that a slow spell of the shared machine falls on both. Prints each run's wall and CPU time
# (GNU time's %e and %U + %S) and the medians per binary, and with --old the ratios new / old
# of the medians (CPU time is the steadier figure on a shared machine).
#
#   bench/bench_file.sh FILE [--binary build/allanlot] [--old OLD_BINARY] [--threads 2]
#                       [--runs 3] [--workdir ${TMPDIR:-/tmp}/allanlot-bench-file]
set -euo pipefail

[ $# -ge 1 ] || { echo "usage: bench_file.sh FILE [--binary B] [--old B] [--threads T] [--runs N]" >&2; exit 2; }
file="$1"
shift
binary="$(dirname "$0")/../build/allanlot"
old=""
threads=2
runs=3
workdir="${TMPDIR:-/tmp}/allanlot-bench-file"
while [ $# -gt 0 ]; do
  case "$1" in
    --binary) binary="$2"; shift 2 ;;
    --old) old="$2"; shift 2 ;;
    --threads) threads="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --workdir) workdir="$2"; shift 2 ;;
    *) echo "bench_file: unknown option $1" >&2; exit 2 ;;
  esac
done
[ -f "$file" ] || { echo "bench_file: no recording at $file" >&2; exit 2; }
[[ "$runs" =~ ^[1-9][0-9]*$ ]] || { echo "bench_file: --runs must be a positive integer" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "bench_file: needs GNU time (apt-get install time)" >&2; exit 2; }
binaries=("$binary")
[ -z "$old" ] || binaries+=("$old")
for b in "${binaries[@]}"; do
  [ -x "$b" ] || { echo "bench_file: no binary at $b" >&2; exit 2; }
done
mkdir -p "$workdir"

declare -A walls cpus
for ((r = 1; r <= runs; r++)); do
  for i in "${!binaries[@]}"; do
    out="$workdir/out-$i"
    rm -rf "$out"
    if ! /usr/bin/time -f "%e %U %S" -o "$workdir/time.txt" \
      "${binaries[$i]}" analyze --force --quiet --threads "$threads" -o "$out" "$file" \
      2>"$workdir/stderr.txt"; then
      echo "bench_file: analyze failed (${binaries[$i]}, run $r):" >&2
      cat "$workdir/stderr.txt" >&2
      exit 1
    fi
    read -r wall user sys < <(tail -n 1 "$workdir/time.txt")
    cpu=$(awk -v u="$user" -v s="$sys" 'BEGIN {print u + s}')
    echo "run $r ${binaries[$i]}: wall $wall s, CPU $cpu s"
    walls[$i]="${walls[$i]:-} $wall"
    cpus[$i]="${cpus[$i]:-} $cpu"
  done
done

median() { tr ' ' '\n' | grep . | sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
m_new=$(echo "${walls[0]}" | median)
c_new=$(echo "${cpus[0]}" | median)
echo "median ${binaries[0]}: wall $m_new s, CPU $c_new s ($runs runs, $threads threads, $(basename "$file"))"
if [ -n "$old" ]; then
  m_old=$(echo "${walls[1]}" | median)
  c_old=$(echo "${cpus[1]}" | median)
  echo "median $old: wall $m_old s, CPU $c_old s"
  awk -v a="$m_new" -v b="$m_old" -v c="$c_new" -v d="$c_old" \
    'BEGIN {printf "new / old: wall %.3f, CPU %.3f\n", a / b, c / d}'
fi
