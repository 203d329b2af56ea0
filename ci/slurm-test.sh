#!/usr/bin/env bash
# The cluster path on a real Slurm (issue 17), for `make test-cluster`.
#
# Installs Debian's slurm-wlm and munge when they are missing (apt-get; needs
# root), starts a private munged, slurmctld and slurmd for one node of this
# machine (their own socket, ports, state and spool under a temporary
# directory; nothing in /etc is changed), and then:
#
#   A. submits the array script of `metabezier slurm` for a small campaign
#      with --out (3 tasks, 2 at a time), merges with `metabezier merge DIR`
#      and compares runs.csv, convergence.csv, hits.csv, spec.toml and
#      meta.toml byte for byte with a whole run;
#   B. submits it again without --out, stops one task in the middle of its
#      shard (scontrol suspend, so that it is certainly mid-run), requeues it
#      (scontrol requeue), and checks that the task resumed its journal and
#      that the merged files are still identical.
#
# Only the daemons this script started are stopped, by their pids. Set
# KEEP=1 to keep the temporary directory (it is kept on failure).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
START=$(date +%s)
CTLD_PORT=${SLURM_TEST_PORT:-16817}
SLURMD_PORT=$((CTLD_PORT + 1))

say() { printf 'slurm-test [%3ss]: %s\n' "$(($(date +%s) - START))" "$*"; }
fail() {
	say "FAILED: $*"
	exit 1
}

if [ "$(id -u)" != 0 ]; then
	fail "needs root (it installs packages and starts slurmd)"
fi

# --- install -----------------------------------------------------------------
if ! command -v slurmctld >/dev/null || ! command -v slurmd >/dev/null ||
	! command -v sbatch >/dev/null || ! command -v munged >/dev/null; then
	say "installing slurm-wlm and munge"
	apt-get update -qq
	DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
		slurm-wlm munge >/dev/null
fi
say "$(slurmctld -V), munge $(munged -V 2>&1 | awk '{print $1}')"

cargo build --release --locked --quiet
BIN=$ROOT/target/release/metabezier

# --- private daemons ---------------------------------------------------------
T=$(mktemp -d /tmp/metabezier-slurm.XXXXXX)
PIDS=()
JOBS=()
cleanup() {
	local rc=$?
	set +e
	for j in "${JOBS[@]}"; do scancel "$j" 2>/dev/null; done
	if [ "$rc" != 0 ]; then
		for f in "$T"/log/*.log "$T"/*/slurm-*.out; do
			[ -f "$f" ] && {
				echo "--- $f"
				tail -n 30 "$f"
			}
		done
	fi
	# Stop what we started, newest first: slurmd, slurmctld, munged.
	for ((i = ${#PIDS[@]} - 1; i >= 0; i--)); do
		kill "${PIDS[i]}" 2>/dev/null
		wait "${PIDS[i]}" 2>/dev/null
	done
	if [ "$rc" = 0 ] && [ "${KEEP:-0}" != 1 ]; then
		rm -rf "$T"
	else
		echo "slurm-test: kept $T"
	fi
	exit "$rc"
}
trap cleanup EXIT

mkdir -p "$T/munge" "$T/state" "$T/spool" "$T/log"
chmod 700 "$T/munge"
head -c 1024 /dev/urandom >"$T/munge/munge.key"
chmod 400 "$T/munge/munge.key"
munged --foreground --force --socket="$T/munge/munge.sock" \
	--key-file="$T/munge/munge.key" --pid-file="$T/munge/munged.pid" \
	--seed-file="$T/munge/munged.seed" --log-file="$T/log/munged.log" \
	2>>"$T/log/munged.log" &
PIDS+=($!)
for _ in $(seq 50); do [ -S "$T/munge/munge.sock" ] && break; sleep 0.1; done
[ -S "$T/munge/munge.sock" ] || fail "munged did not start"

HOST=$(hostname -s)
export SLURM_CONF=$T/slurm.conf
cat >"$SLURM_CONF" <<EOF
ClusterName=metabezier-ci
SlurmctldHost=$HOST(127.0.0.1)
SlurmctldPort=$CTLD_PORT
SlurmdPort=$SLURMD_PORT
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
# A requeued job waits for its old credential to expire: 5 s, not 120.
AuthInfo=socket=$T/munge/munge.sock,cred_expire=5
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/log/slurmctld.log
SlurmdLogFile=$T/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
SchedulerType=sched/builtin
# Test pending jobs every second (default 60 s), so a requeued task starts
# as soon as its begin time has passed.
SchedulerParameters=sched_interval=1
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
ReturnToService=2
MinJobAge=600
NodeName=mbci NodeHostname=$HOST NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN
PartitionName=ci Nodes=mbci Default=YES MaxTime=INFINITE State=UP
EOF
slurmctld -D -f "$SLURM_CONF" >>"$T/log/slurmctld.out" 2>&1 &
PIDS+=($!)
slurmd -D -N mbci -f "$SLURM_CONF" >>"$T/log/slurmd.out" 2>&1 &
PIDS+=($!)
for _ in $(seq 100); do
	[ "$(sinfo -h -n mbci -o %t 2>/dev/null)" = idle ] && break
	sleep 0.2
done
[ "$(sinfo -h -n mbci -o %t 2>/dev/null)" = idle ] || fail "the node did not come up"
say "munged, slurmctld and slurmd up (pids ${PIDS[*]}), node mbci idle with 2 CPUs"

# --- the campaign ------------------------------------------------------------
# 3 functions x 3 algorithms x 6 runs: 54 runs, 18 per shard, each shard a
# few seconds on one CPU; hits.csv is written (benchmark problems).
cat >"$T/slurm_ci.toml" <<'EOF'
[experiment]
name = "slurm_ci"
seed = 17
runs = 6
budget = 400000

[[problem]]
function = ["sphere", "rastrigin", "ackley"]
dim = 30

[[algorithm]]
name = "hs"

[[algorithm]]
name = "pso"

[[algorithm]]
name = "mhs"
EOF
"$BIN" run "$T/slurm_ci.toml" --out "$T/whole" --threads 2 --quiet >/dev/null
say "whole run done"

# Waits until job $1 has left the queue, then checks that every task
# completed with exit code 0.
await() {
	for i in $(seq 900); do
		[ -z "$(squeue -h -j "$1" 2>/dev/null)" ] && break
		# A relaunch that raced the old step's cleanup ("batch script setup
		# failed ... File exists") is requeued held; let it go again.
		if [ $((i % 10)) -eq 0 ] && squeue -h -j "$1" -o '%r' 2>/dev/null | grep -qi 'held'; then
			scontrol release "$1" 2>/dev/null || true
		fi
		sleep 0.2
	done
	[ -z "$(squeue -h -j "$1")" ] || fail "job $1 still queued after 3 minutes"
	local states
	states=$(scontrol show job -o "$1" | grep -o 'JobState=[A-Z]* .* ExitCode=[0-9:]*' |
		sed 's/JobState=\([A-Z]*\) .* ExitCode=\(.*\)/\1 \2/' | sort | uniq -c)
	[ "$(echo "$states" | awk '{print $2, $3}')" = "COMPLETED 0:0" ] ||
		fail "job $1 ended as: $states"
}

# Compares the merged files in $1 with the whole run.
same() {
	for f in runs.csv convergence.csv hits.csv spec.toml meta.toml; do
		cmp "$T/whole/$f" "$1/$f" || fail "$1/$f differs from the whole run"
	done
}

# A: with --out, all three tasks into one directory on the "shared" disk.
mkdir "$T/a"
cd "$T/a"
"$BIN" slurm "$T/slurm_ci.toml" --tasks 3 --out "$T/a/scratch" --cpus 1 \
	--time 00:05:00 --sbatch "--partition=ci" >job.sbatch
JOB=$(sbatch --parsable job.sbatch)
JOBS+=("$JOB")
say "A: submitted array job $JOB"
await "$JOB"
# The merge command the script names in its comment, as it stands.
MERGE=$(sed -n 's/^#   \(.* merge .*\)$/\1/p' job.sbatch)
[ -n "$MERGE" ] || fail "job.sbatch names no merge command"
eval "$MERGE"
same "$T/a/scratch"
say "A: 3 tasks completed; merged files identical to the whole run"

# B: default output directory; task 1 is stopped mid-shard and requeued.
mkdir "$T/b"
cd "$T/b"
"$BIN" slurm "$T/slurm_ci.toml" --tasks 3 --cpus 1 >job.sbatch
JOB=$(sbatch --parsable job.sbatch)
JOBS+=("$JOB")
SHARD=$T/b/results/slurm_ci/shard-2-of-3
say "B: submitted array job $JOB"
# Stop it once a few runs are journalled (of 18).
finished() {
	local n
	n=$(grep -c ',ok$' "$SHARD/journal.csv" 2>/dev/null || true)
	echo "${n:-0}"
}
for _ in $(seq 1500); do
	[ "$(finished)" -ge 4 ] && break
	sleep 0.05
done
scontrol suspend "${JOB}_1"
DONE=$(finished)
if [ -e "$SHARD/runs.csv" ] || [ "$DONE" -lt 1 ] || [ "$DONE" -ge 18 ]; then
	fail "task 1 was not mid-shard when suspended ($DONE of 18 runs); use a larger budget"
fi
scontrol requeue "${JOB}_1"
say "B: task 1 suspended with $DONE of 18 runs journalled, and requeued"
# A job requeued while suspended may be held; release it once its old
# batch step has gone (its spool directory removed), so that the relaunch
# does not meet the old step's files on a loaded machine.
for _ in $(seq 100); do
	state=$(scontrol show job -o "${JOB}_1" | grep -o 'JobState=[A-Z]*')
	[ "$state" = JobState=PENDING ] && break
	sleep 0.1
done
TASK_ID=$(scontrol show job -o "${JOB}_1" | grep -o '^JobId=[0-9]*' | cut -d= -f2)
for _ in $(seq 200); do
	[ -d "$T/spool/job$(printf %05d "$TASK_ID")" ] || break
	sleep 0.1
done
scontrol release "${JOB}_1" 2>/dev/null || true
await "$JOB"
scontrol show job -o "${JOB}_1" | grep -Eq 'Restarts=[1-9]' || fail "task 1 did not restart"
grep -q 'DUE TO JOB REQUEUE' "slurm-${JOB}_1.out" || fail "task 1 was not requeued"
# Its second start kept the runs of the first, which had not finished.
REUSED=$(sed -n 's/.*18 runs (\([0-9]*\) reused.*/\1/p' "slurm-${JOB}_1.out")
if [ -z "$REUSED" ] || [ "$REUSED" -lt "$DONE" ] || [ "$REUSED" -ge 18 ]; then
	fail "the requeued task did not resume a shard killed mid-run (reused: '$REUSED')"
fi
"$BIN" merge results/slurm_ci
same "$T/b/results/slurm_ci"
say "B: requeued task kept $REUSED finished runs; merged files identical to the whole run"
say "passed in $(($(date +%s) - START)) s"
