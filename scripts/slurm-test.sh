#!/usr/bin/env bash
# A sweep through a real Slurm cluster of one node on this machine, against the same sweep run
# locally and through GNU parallel. Installs slurm-wlm, munge and parallel (Debian), starts munged,
# slurmctld and slurmd on localhost from a slurm.conf generated in a temporary folder (cgroups
# off: proctrack/linuxproc, task/none; job completions in a text file that sacct reads), submits
# the script `chainmail sweep --slurm` writes, waits, and compares the gathered sweep with the
# local one: every point's final hash and every error and verdict in sweep.csv must be equal.
# Stops the daemons it started and removes the folder. Needs root (or sudo) for the packages and
# the daemons; it is not part of ctest (docs/command-line.md, `chainmail sweep`).
#   ./scripts/slurm-test.sh [BUILD_DIR]     (default build/release, already built)
set -euo pipefail
cd "$(dirname "$0")/.."
chainmail=$(realpath "${1:-build/release}")/bench/chainmail
[ -x "$chainmail" ] || { echo "slurm-test: no $chainmail: build first"; exit 2; }
sudo_cmd=""
[ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"

missing=()
for p in slurm-wlm munge parallel; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

work=$(mktemp -d "${TMPDIR:-/tmp}/chainmail-slurm.XXXXXX")
chmod 755 "$work"
pids=()
stop() {
  for pid in "${pids[@]}"; do $sudo_cmd kill "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do while $sudo_cmd kill -0 "$pid" 2>/dev/null; do sleep 0.2; done; done
  rm -rf "$work"
}
trap stop EXIT
seconds() { date +%s.%N; }
took() { awk -v a="$1" -v b="$(seconds)" 'BEGIN { printf "%.1f", b - a }'; }

# munge: a key of our own, its socket in the work folder
$sudo_cmd dd if=/dev/urandom of="$work/munge.key" bs=1024 count=1 status=none
$sudo_cmd chmod 400 "$work/munge.key"
$sudo_cmd munged --force --foreground --key-file="$work/munge.key" --socket="$work/munge.socket" \
  --pid-file="$work/munged.pid" --log-file="$work/munged.log" --seed-file="$work/munge.seed" \
  >"$work/munged.out" 2>&1 &
pids+=($!)
for _ in $(seq 50); do [ -S "$work/munge.socket" ] && break; sleep 0.1; done

# slurm.conf: one node, this host, every CPU; ports chosen free
host=$(hostname -s)
port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("",0)); print(s.getsockname()[1])')
mkdir -p "$work/state" "$work/spool"
export SLURM_CONF="$work/slurm.conf"
cat > "$SLURM_CONF" <<CONF
ClusterName=chainmail
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=$(id -un)
AuthType=auth/munge
AuthInfo=socket=$work/munge.socket
CredType=cred/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=$work/jobcomp.txt
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MpiDefault=none
NodeName=$host NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=test Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
$sudo_cmd env SLURM_CONF="$SLURM_CONF" slurmctld -D -i >"$work/slurmctld.out" 2>&1 &
pids+=($!)
$sudo_cmd env SLURM_CONF="$SLURM_CONF" slurmd -D >"$work/slurmd.out" 2>&1 &
pids+=($!)
for _ in $(seq 100); do sinfo -h -o %T 2>/dev/null | grep -qx idle && break; sleep 0.2; done
sinfo

# the sweep: an 8 x 8 curtain, plausible and ODE at three dt values each
scene=$(realpath bench/scenes/curtain.json)
sweep=("$chainmail" sweep "$scene" --vary 'backends.{backend}.dt=0.004,0.002,0.001'
       --backends plausible,ode --set weave.rows=8 --set weave.cols=8)

start=$(seconds)
"${sweep[@]}" --out "$work/local" --cache "$work/cache-local" --jobs "$(nproc)" 2>/dev/null
local_s=$(took "$start")

start=$(seconds)
"${sweep[@]}" --out "$work/parallel" --cache "$work/cache-parallel" --print-jobs > "$work/jobs.txt"
head -n 1 "$work/jobs.txt" | sh 2>/dev/null
tail -n +2 "$work/jobs.txt" | parallel -j "$(nproc)"
"${sweep[@]}" --cache "$work/cache-parallel" --gather "$work/parallel" 2>/dev/null
parallel_s=$(took "$start")

start=$(seconds)
"${sweep[@]}" --out "$work/slurm" --cache "$work/cache-slurm" --slurm "$work/sweep.sbatch"
bash "$work/sweep.sbatch"
for _ in $(seq 1800); do [ -z "$(squeue -h)" ] && break; sleep 0.5; done
slurm_s=$(took "$start")
echo "== sacct"
sacct -c --format=JobID,JobName%20,State,ExitCode,Elapsed,Start,End,NCPUS 2>/dev/null || cat "$work/jobcomp.txt"

# equal: every point's final hash, and every column of sweep.csv but the timings
status=0
compare() {
  local a=$1 b=$2 name=$3
  for k in $(ls "$a/points" | grep -E '^[0-9]+$'); do
    ha=$(python3 -c 'import json,sys; s=json.load(open(sys.argv[1])); print([b["hash"] for b in s["backends"].values()][0])' "$a/points/$k/summary.json")
    hb=$(python3 -c 'import json,sys; s=json.load(open(sys.argv[1])); print([b["hash"] for b in s["backends"].values()][0])' "$b/points/$k/summary.json" 2>/dev/null || echo missing)
    [ "$ha" = "$hb" ] || { echo "slurm-test: $name point $k: hash $hb, local $ha"; status=1; }
  done
  # backend, the axis, error_m, catenary_error, stable, verdict (not the timings)
  if ! diff <(cut -d, -f1,2,5- "$a/sweep.csv") <(cut -d, -f1,2,5- "$b/sweep.csv" 2>/dev/null); then
    echo "slurm-test: $name sweep.csv differs from the local one"; status=1
  fi
}
compare "$work/local" "$work/parallel" parallel
compare "$work/local" "$work/slurm" slurm
[ -s "$work/slurm/sweep.png" ] || [ ! -s "$work/local/sweep.png" ] || { echo "slurm-test: no plot"; status=1; }
echo "== $(ls "$work/local/points" | grep -cE '^[0-9]+$') points; wall s: local $local_s, parallel $parallel_s, slurm $slurm_s"
cat "$work/slurm/sweep.csv"
[ $status -eq 0 ] && echo "slurm-test: ok" || echo "slurm-test: FAILED"
exit $status
