#!/usr/bin/env bash
# The cluster check, on a real one-node Slurm: installs Debian's slurm and munge, starts
# munged, slurmctld and slurmd from a fresh scratch folder, then
#   1. submits a sweep as a 4-task job array with `monoculus slurm --submit`, waits for its
#      merge job, and checks that the merged folder equals a single-machine run;
#   2. submits a slower sweep, cancels one array task mid-run (scancel), resubmits that
#      shard, merges, and checks that nothing is lost or duplicated.
# The daemons are stopped at the end, whatever happened. Runs locally as in CI (as root).
#
# Usage: scripts/slurm-ci.sh [MONOCULUS_BINARY]   (default: target/debug/monoculus)
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
BIN=$(realpath "${1:-target/debug/monoculus}")
[ -x "$BIN" ] || { echo "slurm-ci: no binary at $BIN (build it first)" >&2; exit 1; }

log() { echo "slurm-ci: $*" >&2; }
fail() { log "FAILED: $*"; exit 1; }

# --- install -----------------------------------------------------------------------
if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null || ! command -v sbatch >/dev/null; then
  log "installing slurm and munge from Debian's packages"
  export DEBIAN_FRONTEND=noninteractive
  install() {
    apt-get update -qq &&
      apt-get install -y -qq --no-install-recommends slurmctld slurmd slurm-client munge >/dev/null
  }
  install || { log "install failed, retrying once"; sleep 5; install; }
fi

# --- scratch, config -----------------------------------------------------------------
for port in 6817 6818; do
  if (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null; then
    fail "port $port is in use (another slurm running?)"
  fi
done
S=$(mktemp -d /tmp/monoculus-slurm.XXXXXX)
chmod 755 "$S"
mkdir -p "$S/state" "$S/spool" "$S/log" "$S/work"
CPUS=$(nproc)
MEM=$(( $(free -m | awk '/^Mem:/ {print $2}') * 8 / 10 ))
export SLURM_CONF="$S/slurm.conf"
cat > "$SLURM_CONF" <<CONF
ClusterName=monoculus-ci
SlurmctldHost=localhost
SlurmUser=root
AuthType=auth/munge
StateSaveLocation=$S/state
SlurmdSpoolDir=$S/spool
SlurmctldPidFile=$S/slurmctld.pid
SlurmdPidFile=$S/slurmd.pid
SlurmctldLogFile=$S/log/slurmctld.log
SlurmdLogFile=$S/log/slurmd.log
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
MpiDefault=none
ReturnToService=2
MinJobAge=600
SchedulerParameters=batch_sched_delay=0,sched_min_interval=0
NodeName=localhost NodeAddr=127.0.0.1 CPUs=$CPUS RealMemory=$MEM State=UNKNOWN
PartitionName=ci Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF

# --- start, and stop whatever happens ------------------------------------------------------
MUNGED_STARTED=0
stop() {
  local rc=$?
  log "stopping the daemons"
  scontrol shutdown >/dev/null 2>&1 || true
  for f in "$S/slurmctld.pid" "$S/slurmd.pid"; do
    if [ -f "$f" ]; then
      local pid; pid=$(cat "$f")
      for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
      kill -9 "$pid" 2>/dev/null || true
    fi
  done
  if [ "$MUNGED_STARTED" = 1 ]; then
    pkill -x munged 2>/dev/null || true
  fi
  if [ "$rc" != 0 ]; then
    log "slurmctld log (tail):"; tail -n 30 "$S/log/slurmctld.log" >&2 2>/dev/null || true
    log "slurmd log (tail):"; tail -n 30 "$S/log/slurmd.log" >&2 2>/dev/null || true
    for f in "$S"/work/*/slurm/logs/*.out; do
      [ -f "$f" ] && { log "$f:"; tail -n 5 "$f" >&2; }
    done
  fi
  rm -rf "$S"
  exit "$rc"
}
trap stop EXIT

if ! pgrep -x munged >/dev/null; then
  mkdir -p /run/munge /var/log/munge /var/lib/munge
  chown munge:munge /run/munge /var/log/munge /var/lib/munge
  chmod 0755 /run/munge
  if [ ! -f /etc/munge/munge.key ]; then
    mungekey --create
    chown munge:munge /etc/munge/munge.key
    chmod 0400 /etc/munge/munge.key
  fi
  su -s /bin/sh munge -c /usr/sbin/munged
  MUNGED_STARTED=1
fi
slurmctld
slurmd -N localhost
for _ in $(seq 100); do
  state=$(sinfo -h -o %T 2>/dev/null | head -1 || true)
  [ "$state" = idle ] && break
  sleep 0.2
done
[ "$state" = idle ] || fail "the node never became idle (state: ${state:-none})"
log "slurm is up: $(sinfo -h -o '%P %D %c %T')"

# --- helpers -------------------------------------------------------------------------------
# The state of job (or task) $1 as scontrol shows it, e.g. COMPLETED.
job_state() { scontrol show job "$1" 2>/dev/null | grep -o 'JobState=[A-Z_]*' | head -1 | cut -d= -f2; }
# Waits until job $1 is in one of the states $2 (a |-list), at most $3 seconds.
wait_state() {
  local job=$1 want=$2 limit=$3 s
  for _ in $(seq $((limit * 5))); do
    s=$(job_state "$job")
    if [[ "|$want|" == *"|$s|"* ]]; then echo "$s"; return 0; fi
    sleep 0.2
  done
  fail "job $job not in $want after ${limit}s (state: ${s:-gone})"
}
# Checks that results folder $1 equals $2 but wall_ms: runs.csv row by row and summary.csv.
same_results() {
  python3 - "$1" "$2" <<'PY'
import csv, sys
a, b = sys.argv[1], sys.argv[2]
def rows(d):
    with open(f"{d}/runs.csv", newline="") as f:
        r = list(csv.reader(f))
    wall = r[0].index("wall_ms")
    return [[v for i, v in enumerate(row) if i != wall] for row in r]
ra, rb = rows(a), rows(b)
keys = [(row[1], row[ra[0].index("seed")]) for row in ra[1:]]
assert len(keys) == len(set(keys)), f"{a}: duplicated runs"
assert ra == rb, f"{a}/runs.csv and {b}/runs.csv differ ({len(ra) - 1} and {len(rb) - 1} rows)"
sa, sb = (open(f"{d}/summary.csv").read() for d in (a, b))
assert sa == sb, "summary.csv differs"
print(f"slurm-ci: {a} equals {b}: {len(ra) - 1} runs, each once", file=sys.stderr)
PY
}
submit_ids() { sed -n "s/^$1=//p"; }

W="$S/work"
# --- 1. a sweep as a job array, merged -----------------------------------------------------
CFG="$ROOT/configs/ci/slurm_sweep.toml"
"$BIN" run "$CFG" --out "$W/single" >/dev/null
out=$("$BIN" slurm "$CFG" --shards 4 --out "$W/array" --cpus-per-task 1 --time 00:10:00 --submit)
array=$(echo "$out" | submit_ids array_job); merge=$(echo "$out" | submit_ids merge_job)
[ -n "$array" ] && [ -n "$merge" ] || fail "monoculus slurm --submit printed no job ids: $out"
log "sweep: array job $array, merge job $merge"
st=$(wait_state "$merge" "COMPLETED|FAILED|CANCELLED|TIMEOUT" 180)
[ "$st" = COMPLETED ] || fail "merge job $merge ended $st"
for k in 0 1 2 3; do
  [ "$(job_state "${array}_$k")" = COMPLETED ] || fail "task ${array}_$k: $(job_state "${array}_$k")"
done
same_results "$W/array" "$W/single"
grep -q "job = \"${array}_" "$W/array/provenance.toml" || fail "provenance.toml names no array task"

# --- 2. a task cancelled mid-run, resubmitted ------------------------------------------------
CFG="$ROOT/configs/ci/slurm_slow.toml"
out=$("$BIN" slurm "$CFG" --shards 4 --out "$W/cancel" --cpus-per-task 1 --submit)
array=$(echo "$out" | submit_ids array_job); merge=$(echo "$out" | submit_ids merge_job)
log "slow sweep: array job $array, merge job $merge"
victim="${array}_2"
wait_state "$victim" "RUNNING" 180 >/dev/null
shard="$W/cancel/shards/2-of-4.csv"
for _ in $(seq 600); do
  [ -f "$shard" ] && [ "$(wc -l < "$shard")" -ge 3 ] && break
  sleep 0.1
done
[ "$(wc -l < "$shard")" -ge 3 ] || fail "shard 2 wrote no rows"
scancel "$victim"
st=$(wait_state "$victim" "CANCELLED|COMPLETED" 60)
[ "$st" = CANCELLED ] || fail "task $victim ended $st before it could be cancelled (make the shards slower)"
before=$(( $(wc -l < "$shard") - 1 ))
log "cancelled $victim after $before finished runs"
for k in 0 1 3; do wait_state "${array}_$k" "COMPLETED" 300 >/dev/null; done
# The merge job waits on a dependency that can no longer be satisfied.
scancel "$merge" || true
if "$BIN" merge "$W/cancel" 2> "$S/merge.err"; then fail "merge of an incomplete folder succeeded"; fi
grep -q "shard 2/4 (" "$S/merge.err" || fail "merge did not name shard 2/4: $(cat "$S/merge.err")"
# Resubmit that one shard, then the merge.
again=$(sbatch --parsable --array=2 "$W/cancel/slurm/array.sh" | cut -d';' -f1)
merge=$(sbatch --parsable --dependency="afterok:$again" "$W/cancel/slurm/merge.sh" | cut -d';' -f1)
log "resubmitted shard 2 as $again, merge job $merge"
st=$(wait_state "$merge" "COMPLETED|FAILED|CANCELLED|TIMEOUT" 300)
[ "$st" = COMPLETED ] || fail "merge job $merge ended $st"
grep -q "already done" "$W/cancel/slurm/logs/"*"-${again}_2.out" 2>/dev/null ||
  grep -rq "$before already done" "$W/cancel/slurm/logs/" || fail "the resubmitted shard did not resume"
attempts=$(grep -c '^\[\[attempt\]\]' "$W/cancel/shards/2-of-4.toml")
[ "$attempts" -ge 2 ] || fail "shard 2's provenance records $attempts attempts"
"$BIN" run "$CFG" --out "$W/cancel-single" >/dev/null
same_results "$W/cancel" "$W/cancel-single"
log "passed: 2 sweeps on Slurm, one task cancelled and resubmitted, merged = single machine"
