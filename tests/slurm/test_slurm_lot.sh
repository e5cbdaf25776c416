#!/usr/bin/env bash
# slurm.lot: slurm/submit-lot against a real single-node Slurm that this test starts itself.
#
#   tests/slurm/test_slurm_lot.sh ALLANLOT_BINARY
#
# Installs munge and Slurm (Debian packages) when missing and running as root; otherwise, if they
# are missing, skips (exit 77). Starts munged, slurmctld and slurmd from a temporary directory
# (free ports, own sockets, state and logs; nothing under /etc or /run), simulates a small lot,
# submits it with a corrupt and an absent recording in the manifest and a spec, and checks the
# results files, the merged summary with the spec's verdicts, the report of what is missing, that
# a spec with errors is refused before anything is submitted, and that a resubmission redoes only
# what is missing. Stops exactly the daemons it started, by pid, on every exit path, and removes the
# temporary directory (kept with ALLANLOT_SLURM_TEST_KEEP=1).
#
# ALLANLOT_SLURM_TEST_RESUME=0 skips the last step, which resubmits every recording (--all) and
# needs `allanlot analyze` to skip results files that are complete and current (resume).
set -euo pipefail

if [ $# -ne 1 ]; then
  echo "usage: $0 ALLANLOT_BINARY" >&2
  exit 2
fi
allanlot="$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
submit_lot="$repo/slurm/submit-lot"
t_start="$EPOCHREALTIME"

log() { awk -v a="$t_start" -v b="$EPOCHREALTIME" -v m="$*" 'BEGIN { printf "[slurm.lot %5.1fs] %s\n", b - a, m }'; }
fail() {
  echo "FAIL: $*" >&2
  exit 1
}

# ---- packages -----------------------------------------------------------------------------------
packages=(munge slurmctld slurmd slurm-client hdf5-tools)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  if [ "$(id -u)" -ne 0 ]; then
    echo "SKIP: needs ${missing[*]} (not installed, and not root to install them: run scripts/setup)"
    exit 77
  fi
  echo "installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get -o DPkg::Lock::Timeout=300 update -qq >/dev/null
  apt-get -o DPkg::Lock::Timeout=300 install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
if [ "$(id -u)" -ne 0 ]; then
  echo "SKIP: slurmd and munged of a private test cluster need root"
  exit 77
fi

# ---- a private cluster in a temporary directory ---------------------------------------------------
tmp="$(mktemp -d /tmp/allanlot-slurm-test.XXXXXX)"
pids=() # daemons started here, in start order
names=()

stop_daemons() {
  # Jobs first (their slurmstepd are not children of slurmd), then the daemons, newest first.
  if [ -n "${SLURM_CONF:-}" ] && [ ${#pids[@]} -ge 2 ]; then
    local jobs
    jobs="$(squeue -h -o %A 2>/dev/null || true)"
    if [ -n "$jobs" ]; then
      # shellcheck disable=SC2086
      scancel $jobs 2>/dev/null || true
      for _ in $(seq 50); do
        [ -z "$(squeue -h -o %A 2>/dev/null || true)" ] && break
        sleep 0.2
      done
    fi
  fi
  local i pid
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do
    pid="${pids[i]}"
    kill -TERM "$pid" 2>/dev/null || continue
    for _ in $(seq 100); do
      # our children: once dead they are reaped by wait; a zombie counts as stopped
      if ! [ -e "/proc/$pid" ] || [ "$(awk '{print $3}' "/proc/$pid/stat" 2>/dev/null)" = Z ]; then break; fi
      sleep 0.1
    done
    if [ -e "/proc/$pid" ] && [ "$(awk '{print $3}' "/proc/$pid/stat" 2>/dev/null)" != Z ]; then
      echo "warning: ${names[i]} (pid $pid) did not stop on TERM; killing it" >&2
      kill -KILL "$pid" 2>/dev/null || true
    fi
    wait "$pid" 2>/dev/null || true
    log "stopped ${names[i]} (pid $pid)"
  done
  pids=()
  # Anything else still using the private directory was started through this cluster (a job
  # step's slurmstepd outlives slurmd by a moment): give it 5 s, then kill it.
  local left=""
  for _ in $(seq 50); do
    left="$(processes_using_tmp)"
    [ -z "$left" ] && break
    sleep 0.1
  done
  if [ -n "$left" ]; then
    echo "warning: killing processes still using $tmp: $left" >&2
    # shellcheck disable=SC2086
    kill -KILL $left 2>/dev/null || true
  fi
}

processes_using_tmp() { # pids of processes with their cwd or an open file under $tmp
  find /proc/[0-9]*/cwd /proc/[0-9]*/fd -maxdepth 1 \( -lname "$tmp" -o -lname "$tmp/*" \) 2>/dev/null |
    cut -d/ -f3 | sort -u | grep -vx -e "$$" -e "$BASHPID" | tr '\n' ' ' || true
}

cleanup() {
  local rc=$?
  trap - EXIT INT TERM
  if [ "$rc" -ne 0 ] && [ "$rc" -ne 77 ]; then
    echo "---- diagnostics (exit $rc) ----" >&2
    for f in "$tmp"/log/*.log "$tmp"/out/.slurm/*/logs/*.log; do
      [ -f "$f" ] || continue
      echo "== $f" >&2
      tail -n 25 "$f" >&2
    done
  fi
  stop_daemons
  if [ "${ALLANLOT_SLURM_TEST_KEEP:-0}" = 1 ]; then
    echo "kept $tmp" >&2
  else
    rm -rf "$tmp"
  fi
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

# two free TCP ports for slurmctld and slurmd, so that this cluster never meets another one
used_ports=""
while read -r _ local_address _; do
  [[ "$local_address" == *:* ]] && used_ports+="$((16#${local_address##*:}))"$'\n'
done < <(tail -q -n +2 /proc/net/tcp /proc/net/tcp6 2>/dev/null || true)
free_port() {
  local p
  while :; do
    p=$((20000 + RANDOM % 30000))
    grep -qx "$p" <<<"$used_ports" && continue
    used_ports+=$'\n'"$p"
    echo "$p"
    return
  done
}
ctld_port="$(free_port)"
slurmd_port="$(free_port)"
host="$(hostname -s)"

mkdir -p "$tmp"/{munge,state,spool,log,run}
# munged insists that every directory above its socket is searchable by all
chmod 0711 "$tmp" "$tmp/munge"
mungekey --create --keyfile="$tmp/munge/munge.key" 2>/dev/null
chmod 0400 "$tmp/munge/munge.key"
socket="$tmp/munge/munge.socket"
munged --foreground --socket="$socket" --key-file="$tmp/munge/munge.key" \
  --pid-file="$tmp/run/munged.pid" --log-file="$tmp/log/munged.log" \
  --seed-file="$tmp/munge/munged.seed" --origin=127.0.0.1 >"$tmp/log/munged.stderr.log" 2>&1 &
pids+=($!)
names+=(munged)
for _ in $(seq 100); do
  [ -S "$socket" ] && munge -n -S "$socket" 2>/dev/null | unmunge -S "$socket" >/dev/null 2>&1 && break
  kill -0 "${pids[0]}" 2>/dev/null || fail "munged exited (see $tmp/log/munged.log)"
  sleep 0.1
done
munge -n -S "$socket" | unmunge -S "$socket" >/dev/null || fail "munge does not work"

node_line="$(slurmd -C | head -n 1)"
cat >"$tmp/slurm.conf" <<EOF
ClusterName=allanlottest
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$socket
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/run/slurmctld.pid
SlurmdPidFile=$tmp/run/slurmd.pid
SlurmctldLogFile=$tmp/log/slurmctld.log
SlurmdLogFile=$tmp/log/slurmd.log
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
ReturnToService=2
MinJobAge=600
SchedulerParameters=batch_sched_delay=0
$node_line NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=lot Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$tmp/slurm.conf"

slurmctld -D -c >"$tmp/log/slurmctld.stdout.log" 2>&1 &
pids+=($!)
names+=(slurmctld)
slurmd -D >"$tmp/log/slurmd.stdout.log" 2>&1 &
pids+=($!)
names+=(slurmd)
state=""
for i in $(seq 150); do
  for j in 1 2; do kill -0 "${pids[j]}" 2>/dev/null || fail "${names[j]} exited"; done
  state="$(sinfo -h -n "$host" -o %T 2>/dev/null || true)"
  case "$state" in
    idle*) break ;;
    down* | drain*) scontrol update NodeName="$host" State=RESUME 2>/dev/null || true ;;
  esac
  sleep 0.2
  [ "$i" -lt 150 ] || fail "node not idle after 30 s (state: ${state:-none})"
done
log "cluster up: slurmctld :$ctld_port, slurmd :$slurmd_port, node $host $state (pids ${pids[*]})"

# ---- a lot with two bad entries -------------------------------------------------------------------
cat >"$tmp/model.json" <<'EOF'
{
  "sample_rate_hz": 100,
  "channels": {
    "gyro_x":  {"units": "deg/s", "terms": {"N": 0.005, "B": 0.00125}},
    "accel_x": {"units": "m/s^2", "terms": {"N": 0.0003, "B": 0.0002}}
  },
  "lot_spread": {"N": 0.1, "B": 0.2}
}
EOF
"$allanlot" simulate -q --model "$tmp/model.json" --lot 5 --duration 120 -o "$tmp/lot"
head -c 4096 /dev/urandom >"$tmp/lot/corrupt.h5"
# The spec: gyro N = 0.005 deg/s*s^0.5 = 0.3 deg/sqrt(h) (units.hpp) +- 10 % passes 1 deg/sqrt(h);
# accel N = 0.0003 m/s^2*s^0.5 = 0.018 m/s/sqrt(h) fails 0.005 m/s/sqrt(h): every unit fails on
# its accelerometer, and the verdicts quote each value in the spec's own unit.
cat >"$tmp/spec.json" <<'JSON'
{"name": "slurm test grade",
 "channels": {"gyro_*": {"N": {"max": 1, "unit": "deg/sqrt(h)"}},
              "accel_*": {"N": {"max": 0.005, "unit": "m/s/sqrt(h)"}}}}
JSON
echo '{"channels": {"gyro_*": {"N": {"max": -1, "unit": "deg/sqrt(h)"}}}}' >"$tmp/bad_spec.json"
# relative paths (relative to the manifest), a comment, a blank line; shards of 2:
# [1 2] [corrupt absent] [3 4] [5]: the second task fails entirely
cat >"$tmp/lot/lot.txt" <<'EOF'
# a production lot
unit_0001.h5
unit_0002.h5
corrupt.h5
absent.h5

unit_0003.h5
unit_0004.h5
unit_0005.h5
EOF
out="$tmp/out"
submit=("$submit_lot" --allanlot "$allanlot" --shard-size 2 "$tmp/lot/lot.txt" "$out" --cpus-per-task=1 --time=10)

array_id=""
merge_id=""
submit_and_wait() { # args: extra submit-lot options; sets array_id, merge_id, submit_out
  submit_out="$("${submit[@]}" "$@")" || fail "submit-lot exited with $?: $submit_out"
  printf '  | %s\n' "${submit_out//$'\n'/$'\n'  | }"
  merge_id="$(tail -n 1 <<<"$submit_out")"
  [[ "$merge_id" =~ ^[0-9]+$ ]] || fail "last line of submit-lot is not a job id: '$merge_id'"
  array_id="$(sed -n 's/^submit-lot: array job \([0-9]*\):.*/\1/p' <<<"$submit_out" | head -n 1)"
  local deadline=$(($(date +%s) + 240))
  while [ -n "$(squeue -h -j "$merge_id" -o %T 2>/dev/null)" ]; do
    [ "$(date +%s)" -lt "$deadline" ] || fail "merge job $merge_id not finished after 240 s"
    sleep 0.3
  done
  [ -z "$array_id" ] || [ -z "$(squeue -h -j "$array_id" -o %T 2>/dev/null)" ] ||
    fail "array $array_id still running after its merge job"
}
job_state() { scontrol show job "$1" | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p' | head -n 1; }
task_states() { squeue -h -t all -j "$1" -o '%K %T' | sort -n | awk '{printf "%s%s=%s", sep, $1, $2; sep=" "}'; }
stamp() { stat -c '%i %y' "$1"; }
csv_rows() { tail -n +2 "$out/lot_summary.csv"; }
csv_column() { # args: column name; prints that column of every ok row as "device,channel,value"
  awk -v want="$1" -F, '
    NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
    $5 == "ok" { print $1 "," $2 "," $col[want] }' "$out/lot_summary.csv"
}
check_verdicts() { # args: device ids judged against spec.json by the merge job
  # The verdict columns carry no ',' here (no quoting): the channel verdicts, the detail in the
  # spec's units, and the unit's verdict on every row of the unit.
  local id want status
  head -n 1 "$out/lot_summary.csv" | grep -q ',spec_status,spec_detail,' ||
    fail "lot_summary.csv has no verdicts (was the spec given to the merge job?): $(head -n 1 "$out/lot_summary.csv")"
  for id in "$@"; do
    for ch in gyro_x accel_x; do
      want=pass
      [ "$ch" = accel_x ] && want=fail
      status="$(csv_column spec_status | grep "^$id,/imu/$ch," | cut -d, -f3)"
      [ "$status" = "$want" ] || fail "$id /imu/$ch: spec_status '$status', expected $want"
    done
    csv_column spec_detail | grep -q "^$id,/imu/accel_x,N 0\.0[0-9]*±[0-9.e-]* > 0\.005 m/s/sqrt(h)$" ||
      fail "$id accel_x: the detail does not quote N in m/s/sqrt(h): $(csv_column spec_detail | grep "^$id,")"
    csv_column spec_detail | grep -q "^$id,/imu/gyro_x,N 0\.[0-9]*±[0-9.e-]* <= 1 deg/sqrt(h)$" ||
      fail "$id gyro_x: the detail does not quote N in deg/sqrt(h): $(csv_column spec_detail | grep "^$id,")"
    [ "$(csv_column unit_spec_status | grep -c "^$id,.*,fail$")" -eq 2 ] ||
      fail "$id: unit_spec_status is not fail on both rows: $(csv_column unit_spec_status | grep "^$id,")"
  done
}

check_results() { # args: device ids expected to have a valid results file
  local id f
  for id in "$@"; do
    f="$out/$id.allan.h5"
    [ -f "$f" ] || fail "no results file for $id"
    h5ls -r "$f" >"$tmp/h5ls.txt" 2>&1 || fail "$f is not a readable HDF5 file"
    for ch in /imu/gyro_x /imu/accel_x; do
      grep -q "^$ch/allan/oadev/dev " "$tmp/h5ls.txt" || fail "$f has no $ch/allan/oadev/dev"
      grep -q "^$ch/fit/value " "$tmp/h5ls.txt" || fail "$f has no $ch/fit/value"
    done
    # the task ran analyze with OMP_NUM_THREADS = SLURM_CPUS_PER_TASK = 1
    h5dump -a /threads "$f" | grep -q '(0): "1"$' || fail "$f: threads attribute is not 1"
  done
  ! compgen -G "$out/.*.tmp.*" >/dev/null || fail "temporary files left in $out: $(ls -a "$out")"
}
check_summary() { # args: device ids expected in the summary, in order
  # Two ok rows per unit, plus one "failed: no results file" row per manifest entry still
  # missing (the merge job passes --manifest to summarize).
  local n_ok=$((2 * $#)) n_failed n_expected id
  n_failed=$(csv_rows | grep -c ',failed: no results file,' || true)
  n_expected=$((n_ok + n_failed))
  h5ls "$out/lot_summary.h5" | grep -q "^summary " || fail "lot_summary.h5 has no /summary"
  [ "$(csv_rows | grep -c ',ok,' || true)" -eq "$n_ok" ] ||
    fail "lot_summary.csv has $(csv_rows | grep -c ',ok,' || true) ok rows, expected $n_ok: $(cat "$out/lot_summary.csv")"
  [ "$(csv_rows | wc -l)" -eq "$n_expected" ] ||
    fail "lot_summary.csv has $(csv_rows | wc -l) rows, expected $n_expected: $(cat "$out/lot_summary.csv")"
  if [ -f "$out/.slurm/missing.txt" ]; then
    [ "$n_failed" -eq "$(wc -l <"$out/.slurm/missing.txt")" ] ||
      fail "lot_summary.csv lists $n_failed failed recordings, missing.txt $(wc -l <"$out/.slurm/missing.txt")"
  fi
  for id in "$@"; do
    for ch in /imu/accel_x /imu/gyro_x; do
      grep -q "^$id,$ch,[^,]*,12000,ok,$tmp/lot/" "$out/lot_summary.csv" ||
        fail "lot_summary.csv has no ok row for $id $ch"
    done
  done
  h5dump -H -d /summary "$out/lot_summary.h5" | grep -q "DATASPACE  SIMPLE { ( $n_expected )" ||
    fail "lot_summary.h5 /summary does not have $n_expected rows"
}

# ---- 0. a spec with errors is refused before anything is submitted -------------------------------
rc=0
refused="$("${submit[@]}" -- --spec "$tmp/bad_spec.json" 2>&1)" || rc=$?
[ "$rc" -eq 2 ] || fail "submit-lot with a bad spec exited with $rc, expected 2: $refused"
grep -qF "bad_spec.json: channels.gyro_*.N.max: must be >= 0" <<<"$refused" ||
  fail "submit-lot does not name the spec's problem: $refused"
! compgen -G "$out/.slurm/*/" >/dev/null || fail "submit-lot made a submission with a bad spec"
[ -z "$(squeue -h -o %A)" ] || fail "submit-lot submitted jobs with a bad spec"
log "0. ok: a bad spec refused (exit 2), nothing submitted"

# ---- 1. first submission --------------------------------------------------------------------------
# The spec as a user passes it, among analyze's options: it must reach the merge job's summarize.
log "1. submitting 7 recordings (2 bad) in shards of 2, with a spec after --"
submit_and_wait -- --spec "$tmp/spec.json"
grep -q "the merge job judges the lot against the spec" <<<"$submit_out" ||
  fail "submit-lot does not say that the merge job applies the spec"
[ -n "$array_id" ] || fail "submit-lot named no array job"
log "array $array_id: $(task_states "$array_id"); merge $merge_id: $(job_state "$merge_id")"
[ "$(task_states "$array_id")" = "0=COMPLETED 1=FAILED 2=COMPLETED 3=COMPLETED" ] ||
  fail "array tasks: $(task_states "$array_id"), expected only task 1 (corrupt, absent) failed"
# afterany: the merge ran although a task failed, and reports the missing recordings (exit 1)
[ "$(job_state "$merge_id")" = FAILED ] || fail "merge job state $(job_state "$merge_id"), expected FAILED (exit 1: recordings missing)"
subs=("$out"/.slurm/*/)
[ ${#subs[@]} -eq 1 ] || fail "expected one submission directory in $out/.slurm"
sub="${subs[0]%/}"
shards=("$sub"/shards/shard_*.txt)
[ ${#shards[@]} -eq 4 ] || fail "expected 4 shard files in $sub/shards"
[ "$(cat "$sub/status/shard_00001.rc")" = 2 ] || fail "shard 1 status $(cat "$sub/status/shard_00001.rc"), expected 2"
grep -q 'OMP_NUM_THREADS=1' "$sub"/logs/lot-"${array_id}"_0.log || fail "task log does not show OMP_NUM_THREADS=1"

check_results unit_0001 unit_0002 unit_0003 unit_0004 unit_0005
check_summary unit_0001 unit_0002 unit_0003 unit_0004 unit_0005
[ "$(wc -l <"$out/.slurm/missing.txt")" -eq 2 ] || fail "missing.txt: $(cat "$out/.slurm/missing.txt")"
grep -q "^$tmp/lot/corrupt.h5	.*not an HDF5 file" "$out/.slurm/missing.txt" ||
  fail "missing.txt does not name corrupt.h5 with its reason: $(cat "$out/.slurm/missing.txt")"
grep -q "^$tmp/lot/absent.h5	.*no such file" "$out/.slurm/missing.txt" ||
  fail "missing.txt does not name absent.h5 with its reason: $(cat "$out/.slurm/missing.txt")"
[ -f "$sub/spec.json" ] || fail "no copy of the spec in $sub"
grep -qF "against the spec $sub/spec.json" "$sub/logs/merge-$merge_id.log" ||
  fail "the merge log does not name the spec: $(cat "$sub/logs/merge-$merge_id.log")"
check_verdicts unit_0001 unit_0002 unit_0003 unit_0004 unit_0005
log "1. ok: 5 results files, summary of 10 rows with the spec's verdicts, corrupt.h5 and absent.h5 reported missing"

# ---- 2. resubmission redoes only what is missing --------------------------------------------------
# a results file lost (as if its node had crashed before the rename), and the corrupt recording
# replaced by a good one (a sixth unit, device id unit_0006)
declare -A before=()
for id in unit_0001 unit_0002 unit_0004 unit_0005; do before[$id]="$(stamp "$out/$id.allan.h5")"; done
rm "$out/unit_0003.allan.h5"
"$allanlot" simulate -q --model "$tmp/model.json" --lot 6 --duration 120 -o "$tmp/lot6"
cp "$tmp/lot6/unit_0006.h5" "$tmp/lot/corrupt.h5"

log "2. resubmitting the same command"
submit_and_wait -- --spec "$tmp/spec.json"
grep -q "7 recording(s) in .*, 3 to analyse: 2 task(s)" <<<"$submit_out" ||
  fail "resubmission should submit 3 recordings in 2 tasks"
log "array $array_id: $(task_states "$array_id"); merge $merge_id: $(job_state "$merge_id")"
# shards in manifest order: [corrupt.h5 (repaired), absent.h5] fails, [unit_0003] succeeds
[ "$(task_states "$array_id")" = "0=FAILED 1=COMPLETED" ] ||
  fail "array tasks: $(task_states "$array_id"), expected 0 (absent.h5) failed, 1 (unit_0003) ok"
for id in "${!before[@]}"; do
  [ "$(stamp "$out/$id.allan.h5")" = "${before[$id]}" ] || fail "$id.allan.h5 was rewritten although complete"
done
check_results unit_0001 unit_0002 unit_0003 unit_0004 unit_0005 unit_0006
check_summary unit_0001 unit_0002 unit_0003 unit_0004 unit_0005 unit_0006
check_verdicts unit_0001 unit_0002 unit_0003 unit_0004 unit_0005 unit_0006
[ "$(cut -f1 "$out/.slurm/missing.txt")" = "$tmp/lot/absent.h5" ] ||
  fail "missing.txt should list only absent.h5: $(cat "$out/.slurm/missing.txt")"
log "2. ok: only unit_0003, the repaired recording and absent.h5 resubmitted; others untouched"

# ---- 3. nothing missing but absent.h5: its task fails again, the merge still runs -----------------
rm -f "$tmp/lot/absent.h5"
sed -i '/absent.h5/d' "$tmp/lot/lot.txt"
log "3. resubmitting with the absent recording removed from the manifest (the spec as submit-lot's option)"
submit_and_wait --spec="$tmp/spec.json"
grep -q "every recording has its results file; submitting only the merge job" <<<"$submit_out" ||
  fail "a complete lot should submit only the merge job"
[ "$(job_state "$merge_id")" = COMPLETED ] || fail "merge job state $(job_state "$merge_id"), expected COMPLETED"
[ ! -s "$out/.slurm/missing.txt" ] || fail "missing.txt not empty: $(cat "$out/.slurm/missing.txt")"
check_summary unit_0001 unit_0002 unit_0003 unit_0004 unit_0005 unit_0006
check_verdicts unit_0001 unit_0002 unit_0003 unit_0004 unit_0005 unit_0006
# a recording changed after its analysis counts as missing again
touch -d '+1 minute' "$tmp/lot/unit_0002.h5"
[ "$("$repo/slurm/lot-status" --missing "$tmp/lot/lot.txt" "$out")" = "$tmp/lot/unit_0002.h5" ] ||
  fail "lot-status does not report the changed unit_0002.h5 as missing"
touch -r "$tmp/lot/unit_0001.h5" "$tmp/lot/unit_0002.h5"
[ -z "$("$repo/slurm/lot-status" --missing "$tmp/lot/lot.txt" "$out")" ] || fail "lot-status: recordings missing"
log "3. ok: complete lot, merge only; a changed recording is missing again"

# ---- 4. --all: every recording goes to analyze, which must skip the current results (resume) -----
if [ "${ALLANLOT_SLURM_TEST_RESUME:-1}" = 1 ]; then
  for id in unit_0001 unit_0002 unit_0003 unit_0004 unit_0005 unit_0006; do
    before[$id]="$(stamp "$out/$id.allan.h5")"
  done
  log "4. resubmitting every recording (--all)"
  submit_and_wait --all
  [ "$(task_states "$array_id")" = "0=COMPLETED 1=COMPLETED 2=COMPLETED" ] ||
    fail "array tasks: $(task_states "$array_id")"
  for id in "${!before[@]}"; do
    [ "$(stamp "$out/$id.allan.h5")" = "${before[$id]}" ] ||
      fail "$id.allan.h5 was rewritten by analyze although complete and current (needs analyze's resume)"
  done
  check_summary unit_0001 unit_0002 unit_0003 unit_0004 unit_0005 unit_0006
  log "4. ok: analyze skipped every complete results file"
else
  log "4. skipped (ALLANLOT_SLURM_TEST_RESUME=0)"
fi

log "all checks passed"
