#!/usr/bin/env bash
# End-to-end cost of one six-channel 90-minute 1 kHz unit (the embedded demo model, 5.4 M
# samples a channel) through the real binary (docs/performance.md): simulates the unit
# once into WORKDIR/unit (kept for later runs), then runs
#   allanlot analyze --force --quiet --verbose --threads T -o OUT unit_0001.h5
# RUNS times at each thread count, the thread counts alternating (1 2 1 2 ...) so that a slow
# spell of the shared machine does not fall on one count only. Wall, user and system time and
# peak RSS come from GNU time; the stage times from analyze's verbose line
#   allanlot: stage seconds: read R, kernels K[, psd P, fit F], write W (T threads); ...
# read generically as the comma-separated `name value` pairs between "stage seconds:" and " (".
# Prints a Markdown table of the medians per thread count (wall, each stage, CPU = user + sys,
# peak RSS in MB of 10^6 bytes, the 2-thread speed-up = median wall at 1 thread / median wall
# at 2, and peak RSS / one channel's data (5.4e6 x 8 bytes = 43.2 MB), also per thread) and
# writes RESULTS/bench_unit.json with the medians and every run.
#
#   bench/bench_unit.sh [--binary build/allanlot] [--threads "1 2"] [--runs 3]
#                       [--workdir ${TMPDIR:-/tmp}/allanlot-bench-unit] [--results bench/results]
#                       [--duration 5400]
#
# --duration (seconds of data) exists for testing the script; the figures quoted in
# docs/performance.md are for 5400. The simulated unit is reused while its duration and seed match.
set -euo pipefail
cd "$(dirname "$0")/.."

binary="build/allanlot"
threads="1 2"
runs=3
workdir="${TMPDIR:-/tmp}/allanlot-bench-unit"
results="bench/results"
duration=5400
seed=2026
while [ $# -gt 0 ]; do
  case "$1" in
    --binary) binary="$2"; shift 2 ;;
    --threads) threads="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --workdir) workdir="$2"; shift 2 ;;
    --results) results="$2"; shift 2 ;;
    --duration) duration="$2"; shift 2 ;;
    *) echo "bench_unit: unknown option $1" >&2; exit 2 ;;
  esac
done
[ -x "$binary" ] || { echo "bench_unit: no binary at $binary (build the release preset)" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "bench_unit: needs GNU time (apt-get install time)" >&2; exit 2; }
[[ "$runs" =~ ^[1-9][0-9]*$ ]] || { echo "bench_unit: --runs must be a positive integer" >&2; exit 2; }
for t in $threads; do
  [[ "$t" =~ ^[1-9][0-9]*$ ]] || { echo "bench_unit: bad thread count '$t'" >&2; exit 2; }
done

unit_dir="$workdir/unit"
unit="$unit_dir/unit_0001.h5"
stamp="$unit_dir/bench-params.txt"
params="duration $duration seed $seed"
if [ ! -f "$unit_dir/manifest.txt" ] || [ ! -f "$unit" ] || [ "$(cat "$stamp" 2>/dev/null)" != "$params" ]; then
  rm -rf "$unit_dir"
  mkdir -p "$workdir"
  echo "bench_unit: simulating one unit ($duration s) into $unit_dir" >&2
  "$binary" simulate --lot 1 --duration "$duration" --seed "$seed" -o "$unit_dir" --quiet
  echo "$params" >"$stamp"
fi

raw="$workdir/runs.tsv"
: >"$raw"
for ((r = 1; r <= runs; r++)); do
  for t in $threads; do
    out="$workdir/out-$t"
    rm -rf "$out"
    stats="$workdir/time-$t.txt"
    errlog="$workdir/stderr-$t.txt"
    if ! /usr/bin/time -f "%e %U %S %M" -o "$stats" \
      "$binary" analyze --force --quiet --verbose --threads "$t" -o "$out" "$unit" 2>"$errlog"; then
      echo "bench_unit: analyze failed at $t thread(s) (run $r):" >&2
      cat "$errlog" >&2
      exit 1
    fi
    read -r wall user sys rss_kb <"$stats"
    line=$(grep 'stage seconds:' "$errlog" | tail -n 1 || true)
    [ -n "$line" ] || { echo "bench_unit: no 'stage seconds:' line from analyze --verbose:" >&2; cat "$errlog" >&2; exit 1; }
    stages=${line#*stage seconds:}
    stages=${stages%% (*}
    peak_mib=$(sed -n 's/.*peak memory \([0-9.]*\) MiB.*/\1/p' <<<"$line")
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$r" "$t" "$wall" "$user" "$sys" "$rss_kb" \
      "${peak_mib:-}" "$stages" >>"$raw"
    echo "bench_unit: run $r, $t thread(s): ${wall} s" >&2
  done
done

mkdir -p "$results"
python3 - "$raw" "$results/bench_unit.json" "$duration" "$threads" "$runs" "$binary" <<'EOF'
import json, os, socket, statistics, sys, time

raw, out, duration, thread_list, runs, binary = sys.argv[1:7]
channel_bytes = float(duration) * 1000 * 8  # one channel: samples at 1 kHz x 8 bytes

runs_list, stage_names = [], []
for row in open(raw):
    f = row.rstrip("\n").split("\t")
    stages = {}
    for pair in f[7].split(","):
        pair = pair.strip()
        if not pair:
            continue
        name, value = pair.rsplit(" ", 1)
        stages[name] = float(value)
        if name not in stage_names:
            stage_names.append(name)
    runs_list.append({
        "run": int(f[0]), "threads": int(f[1]), "wall_s": float(f[2]),
        "cpu_s": float(f[3]) + float(f[4]), "user_s": float(f[3]), "sys_s": float(f[4]),
        "peak_rss_mb": int(f[5]) * 1024 / 1e6,
        "binary_peak_mib": float(f[6]) if f[6] else None,
        "stages_s": stages,
    })

per_threads = []
for t in [int(x) for x in thread_list.split()]:
    rs = [r for r in runs_list if r["threads"] == t]
    med = lambda key: statistics.median(r[key] for r in rs)
    rss = med("peak_rss_mb")
    entry = {
        "threads": t, "runs": len(rs), "wall_s": med("wall_s"), "cpu_s": med("cpu_s"),
        "stages_s": {s: statistics.median(r["stages_s"].get(s, float("nan")) for r in rs)
                     for s in stage_names},
        "peak_rss_mb": rss,
        "rss_per_channel_data": rss * 1e6 / channel_bytes,
        "rss_per_channel_data_per_thread": rss * 1e6 / channel_bytes / t,
    }
    per_threads.append(entry)
walls = {e["threads"]: e["wall_s"] for e in per_threads}
speedup = walls[1] / walls[2] if walls.get(1) and walls.get(2) else None

doc = {
    "benchmark": "bench_unit",
    "date": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
    "host": socket.gethostname(), "nproc": os.cpu_count(),
    "binary": binary, "duration_s": float(duration), "channels": 6,
    "samples_per_channel": int(float(duration) * 1000), "channel_bytes": channel_bytes,
    "runs_per_thread_count": int(runs), "stage_names": stage_names,
    "medians": per_threads, "speedup_2_threads": speedup, "runs": runs_list,
}
with open(out, "w") as fh:
    json.dump(doc, fh, indent=1)
    fh.write("\n")

fmt = lambda v: "—" if v is None or v != v else f"{v:.2f}"
print(f"One unit, 6 channels x {doc['samples_per_channel']} samples; medians of {runs} run(s)"
      f" per thread count; MB = 10^6 bytes; one channel's data = {channel_bytes / 1e6:.1f} MB.")
print()
print("| threads | wall | " + " | ".join(stage_names) +
      " | CPU | peak RSS | RSS / channel | RSS / channel / thread | speed-up |")
print("|---|---|" + "---|" * len(stage_names) + "---|---|---|---|---|")
for e in per_threads:
    sp = fmt(walls[1] / e["wall_s"]) if e["threads"] != 1 and walls.get(1) and e["wall_s"] else "—"
    print(f"| {e['threads']} | {fmt(e['wall_s'])} s | " +
          " | ".join(f"{fmt(e['stages_s'][s])} s" for s in stage_names) +
          f" | {fmt(e['cpu_s'])} s | {e['peak_rss_mb']:.0f} MB | "
          f"{fmt(e['rss_per_channel_data'])} | {fmt(e['rss_per_channel_data_per_thread'])} | {sp} |")
EOF
echo "wrote $results/bench_unit.json"
