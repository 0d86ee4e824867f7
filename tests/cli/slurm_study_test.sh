#!/usr/bin/env bash
# scripts/slurm-study on a single-node Slurm: starts munged, slurmctld and slurmd (Debian's munge and slurm-wlm) in a
# temporary folder with their own key, sockets, ports and slurm.conf, submits a tiny study as a 2-part job array with
# its dependent merge job, waits for the merge, checks the merged report, and stops the daemons at its end (also on
# failure). CI runs it as root (.ci/run); it needs the packages scripts/deps installs given munge slurm-wlm.
#
# If the daemons cannot start (no munge, a container that forbids them), it says why with their log, and runs the
# same script's parts with the array index set by hand instead (scripts/slurm-study --dry-run, then OUT/part.sh under
# SLURM_ARRAY_TASK_ID=1..2 and OUT/merge.sh).
#
# Usage: tests/cli/slurm_study_test.sh [PBD]   (PBD: an installed pbd; default: the script builds and installs one)
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
pbd_args=()
if [ $# -ge 1 ]; then pbd_args=(--pbd "$1"); fi
[ "$(id -u)" -eq 0 ] || { echo "slurm_study_test: must run as root (it starts munged, slurmctld and slurmd)" >&2; exit 2; }
for p in munged slurmctld slurmd sbatch sinfo; do
  command -v "$p" >/dev/null || { echo "slurm_study_test: $p is missing: scripts/deps munge slurm-wlm" >&2; exit 2; }
done
start=$(date +%s)
tmp=$(mktemp -d /tmp/pbd-slurm.XXXXXX)
chmod 755 "$tmp"  # slurmd and the job (as root) and munged need to reach their files
stop() {  # by the pid files of the daemons this test started, never by name
  for f in "$tmp/slurmd.pid" "$tmp/slurmctld.pid" "$tmp/munge/munged.pid"; do
    if [ -s "$f" ]; then kill "$(cat "$f")" 2>/dev/null || true; fi
  done
  sleep 1
}
trap stop EXIT
trap 'exit 130' INT TERM  # through the EXIT trap: the daemons are stopped however the test ends

# The study: two scenes at one budget, 2 parts. The checks below compare it with the options given here.
study=(--quick --scene rope,cloth30 --budgets 2 --threads 1,2 --solvers colored,jacobi --variants plain)

start_slurm() {
  mkdir -p "$tmp/munge" "$tmp/state" "$tmp/spool"
  chmod 700 "$tmp/munge"
  mungekey --create --keyfile="$tmp/munge/munge.key" || return 1
  munged --force --socket="$tmp/munge/munge.sock" --key-file="$tmp/munge/munge.key" --pid-file="$tmp/munge/munged.pid" \
    --log-file="$tmp/munge/munged.log" --seed-file="$tmp/munge/munged.seed" || return 1
  chmod 755 "$tmp/munge"  # clients (sbatch, the daemons) reach the socket
  local host cpus
  host=$(hostname -s)
  cpus=$(nproc)
  cat >"$tmp/slurm.conf" <<EOF
ClusterName=pbdci
SlurmctldHost=$host
SlurmctldPort=16817
SlurmdPort=16818
AuthType=auth/munge
AuthInfo=socket=$tmp/munge/munge.sock
CredType=cred/munge
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/slurmctld.log
SlurmdLogFile=$tmp/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
MpiDefault=none
ReturnToService=2
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=ci Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
  export SLURM_CONF=$tmp/slurm.conf
  slurmctld -f "$SLURM_CONF" || return 1
  slurmd -f "$SLURM_CONF" || return 1
  for _ in $(seq 1 30); do  # the node registers within seconds
    if [ "$(sinfo -h -o %T 2>/dev/null)" = idle ]; then return 0; fi
    sleep 1
  done
  return 1
}

out=$tmp/study
how="2 array tasks (--shard auto) and the dependent merge, under Slurm"
if start_slurm; then
  echo "slurm_study_test: single-node Slurm up ($(sinfo -h -o '%P %D %T %C')); submitting" >&2
  "$here/scripts/slurm-study" --parts 2 --out "$out" --plots --wait "${pbd_args[@]}" -- "${study[@]}"
  grep -q "Launching batch job" "$tmp/slurmd.log" || { echo "slurm_study_test: FAIL: slurmd ran no job" >&2; exit 1; }
else
  # Why Slurm did not start, as its daemons said it; then the same parts with the index set by hand.
  echo "slurm_study_test: NOTE: Slurm could not start here; its logs:" >&2
  tail -n 5 "$tmp"/munge/munged.log "$tmp"/slurmctld.log "$tmp"/slurmd.log 2>&1 | sed 's/^/  /' >&2 || true
  echo "slurm_study_test: running the job array's parts with SLURM_ARRAY_TASK_ID set by hand" >&2
  how="the 2 parts (--shard auto) and the merge, with the array index set by hand (Slurm did not start)"
  "$here/scripts/slurm-study" --parts 2 --out "$out" --plots --dry-run "${pbd_args[@]}" -- "${study[@]}"
  for i in 1 2; do
    SLURM_ARRAY_TASK_ID=$i SLURM_ARRAY_TASK_MIN=1 SLURM_ARRAY_TASK_MAX=2 SLURM_ARRAY_TASK_COUNT=2 "$out/part.sh"
  done
  "$out/merge.sh"
fi

# The nodes ran the installed program only: the parts' and the merge's scripts call pbd and nothing else.
if grep -Eq 'apt-get|scripts/(build|deps|study)|cmake' "$out/part.sh" "$out/merge.sh"; then
  echo "slurm_study_test: FAIL: a job script builds or installs: $(cat "$out/part.sh" "$out/merge.sh")" >&2
  exit 1
fi
/usr/bin/python3 - "$out" <<'EOF'
import json, os, sys
out = sys.argv[1]
def fail(msg):
    sys.exit(f"slurm_study_test: FAIL: {msg}")
parts = []
for i in (1, 2):
    with open(os.path.join(out, "parts", f"study-{i}.json")) as f:
        parts.append(json.load(f))
    if parts[-1]["study"]["options"]["shard"] != f"{i}/2":
        fail(f"part {i} ran shard {parts[-1]['study']['options']['shard']} (--shard auto from the array index)")
with open(os.path.join(out, "study.json")) as f:
    merged = json.load(f)
if merged["study"]["options"]["shard"] is not None or len(merged["study"]["merged_from"]) != 2:
    fail(f"the merged report: shard {merged['study']['options']['shard']}, from {merged['study']['merged_from']}")
if len(merged["records"]) != sum(len(p["records"]) for p in parts) or not merged["records"]:
    fail(f"the merged report has {len(merged['records'])} records, the parts {[len(p['records']) for p in parts]}")
if {s["name"] for s in merged["scenes"]} != {"rope", "cloth30"}:
    fail(f"the merged report's scenes: {[s['name'] for s in merged['scenes']]}")
commits = {p["study"]["git_commit"] for p in parts}
if len(commits) != 1 or merged["study"]["git_commit"] not in commits:
    fail(f"the parts' commits {commits}, the merged report's {merged['study']['git_commit']}")
for name in ("speed_error.png", "summary.md"):  # drawn by the merge job from the merged report
    if not os.path.isfile(os.path.join(out, "plots", name)) or not os.path.getsize(os.path.join(out, "plots", name)):
        fail(f"no plots/{name}")
if "# pbd " not in open(os.path.join(out, "study.txt")).read():
    fail("no table in study.txt")
EOF
echo "slurm_study_test: ok: $how, in $(( $(date +%s) - start )) s" >&2
stop
trap - EXIT
rm -rf "$tmp"
