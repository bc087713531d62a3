#!/usr/bin/env bash
# slurm.sh BIN_DIR CONFIG OUT
# A real Slurm on this machine (Debian's slurmctld, slurmd, munge): the
# quickstart through `coflow run --launcher srun` must equal the same run
# through mpirun, a component killed under srun must end the step within
# 10 s with the component named, and `--launcher sbatch` must submit a batch
# job that runs it to the end. The daemons run from a temporary directory
# and are stopped by their PIDs at the end, whatever happens.
# Needs root (the daemons run as root here); otherwise, or without Slurm,
# reported as skipped (exit 77).
set -u
bin=$1 cfg=$2 out=$3
here=$(cd "$(dirname "$0")" && pwd)
for p in slurmctld slurmd srun sinfo munged; do
  command -v "$p" >/dev/null 2>&1 || [ -x "/usr/sbin/$p" ] || { echo "SKIP: $p is not installed (scripts/setup installs it)"; exit 77; }
done
[ "$(id -u)" -eq 0 ] || { echo "SKIP: the test Slurm runs its daemons as root"; exit 77; }
export PATH=/usr/sbin:$PATH
rm -rf "$out"; mkdir -p "$out"
tmp=$(mktemp -d /tmp/coflow-slurm.XXXXXX)
pids=()  # the daemons, started in the foreground (-D / -F) in the background
cleanup() {
  if [ -n "${SLURM_CONF:-}" ]; then  # end our jobs first, so that no step outlives slurmd
    scancel --full -u root >/dev/null 2>&1
    for i in $(seq 1 30); do [ -z "$(squeue -h 2>/dev/null)" ] && break; sleep 0.2; done
  fi
  # Step daemons started since this test began (ours): let them finish, then
  # make sure.
  steps() { ps -o pid=,etimes=,stat= -C slurmstepd 2>/dev/null | awk -v age=$((SECONDS + 1)) '$2 <= age && $3 !~ /Z/ { print $1 }'; }
  for i in $(seq 1 50); do [ -z "$(steps)" ] && break; sleep 0.2; done
  for p in $(steps); do kill -9 "$p" 2>/dev/null; done
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done
  for i in $(seq 1 20); do
    alive=0; for p in "${pids[@]}"; do kill -0 "$p" 2>/dev/null && alive=1; done
    [ $alive -eq 0 ] && break; sleep 0.1
  done
  for p in "${pids[@]}"; do kill -9 "$p" 2>/dev/null; done
  rm -rf "$tmp"
}
trap cleanup EXIT
fail() { echo "FAIL: $*"; for l in "$tmp"/*.log "$tmp"/munge/*.log; do [ -f "$l" ] && { echo "--- $l"; tail -n 15 "$l"; }; done; exit 1; }

# munge: its own key and socket in the temporary directory (the socket's
# directory must be reachable by all, the key readable by munge alone).
chmod 755 "$tmp"
mkdir -p "$tmp/munge" "$tmp/munge-key"
dd if=/dev/urandom bs=1 count=1024 of="$tmp/munge-key/munge.key" 2>/dev/null
chown -R munge:munge "$tmp/munge" "$tmp/munge-key"
chmod 755 "$tmp/munge"; chmod 700 "$tmp/munge-key"; chmod 400 "$tmp/munge-key/munge.key"
runuser -u munge -- munged -F --key-file="$tmp/munge-key/munge.key" --socket="$tmp/munge/munge.socket" \
  --pid-file="$tmp/munge/munged.pid" --log-file="$tmp/munge/munged.log" --seed-file="$tmp/munge/munge.seed" &
pids+=($!)
for i in $(seq 1 50); do [ -S "$tmp/munge/munge.socket" ] && break; sleep 0.1; done
[ -S "$tmp/munge/munge.socket" ] || fail "munged did not start"
host=$(hostname -s)
ranks=8
sed -e "s|@HOST@|$host|g" -e "s|@TMP@|$tmp|g" -e "s|@CPUS@|$ranks|g" "$here/slurm.conf.in" >"$tmp/slurm.conf"
mkdir -p "$tmp/state" "$tmp/spool"
export SLURM_CONF=$tmp/slurm.conf
slurmctld -D -f "$SLURM_CONF" >"$tmp/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" >"$tmp/slurmd.out" 2>&1 &
pids+=($!)
for i in $(seq 1 100); do
  sinfo -h -o %t 2>/dev/null | grep -q idle && break
  sleep 0.2
done
sinfo -h -o %t | grep -q idle || fail "the node did not become idle: $(sinfo 2>&1)"
echo "slurm up: $(sinfo -h -o '%P %D %t %c')"

# 1. The quickstart through srun equals the mpirun run (to 0.3 s, before the
# balls land: the launch path is what differs; the test runs alone).
"$bin/coflow" run "$cfg" --set run.output.dir="$out/mpirun" --set run.end_time=0.3 >"$out/mpirun.log" 2>&1 || { tail -n 20 "$out/mpirun.log"; fail "the mpirun run failed"; }
timeout 300 "$bin/coflow" run "$cfg" --launcher srun --set run.output.dir="$out/srun" --set run.end_time=0.3 >"$out/srun.log" 2>&1 \
  || { tail -n 30 "$out/srun.log"; fail "the srun run failed"; }
grep -q "coflow: run '.*' finished" "$out/srun.log" || { cat "$out/srun.log"; fail "no summary table under srun"; }
grep -q "@coflow progress" "$out/srun.log" && fail "raw progress lines under srun"
grep -q '"status": "ok"' "$out/srun/summary.json" || fail "summary.json under srun"
m=$("$bin/coflow-check" compare "$out/mpirun" "$out/srun") || { echo "$m"; fail "compare"; }
echo "$m"
nonzero=$(echo "$m" | grep -E '^[a-z_]+_difference=' | grep -vE '=0\.000000e\+00$')
[ -z "$nonzero" ] || fail "srun and mpirun runs differ: $nonzero"
echo "srun run equals the mpirun run bit for bit"

# 2. A component killed under srun ends the step within 10 s, named.
"$bin/coflow" run "$cfg" --launcher srun --set run.output.dir="$out/killed" --set run.end_time=1000 \
  >"$out/killed.log" 2>&1 &
launcher=$!
for i in $(seq 1 300); do
  victim=$(pgrep -f "coflow-particles .*$out/killed/config.yaml" | head -n 1)
  [ -n "$victim" ] && grep -q "progress" "$out/killed.log" 2>/dev/null && break
  sleep 0.1
done
[ -n "$victim" ] || { kill "$launcher"; fail "coflow-particles never started under srun"; }
kill -9 "$victim"
t0=$(date +%s.%N)
for i in $(seq 1 150); do kill -0 "$launcher" 2>/dev/null || break; sleep 0.1; done
t1=$(date +%s.%N)
if kill -0 "$launcher" 2>/dev/null; then kill "$launcher"; fail "the step still runs 15 s after a component was killed"; fi
wait "$launcher"; rc=$?
took=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.1f", b - a }')
echo "killed component: the step ended in $took s with exit status $rc"
awk -v t="$took" 'BEGIN { exit !(t <= 10) }' || fail "the step took $took s to end (10 s allowed)"
[ "$rc" -ne 0 ] || fail "exit status 0 after a component was killed"
grep -q "run failed in component 'particles'" "$out/killed.log" || { tail -n 20 "$out/killed.log"; fail "the killed component is not named"; }
grep -q '"failed_component": "particles"' "$out/killed/summary.json" || fail "summary.json does not name the component"

# 2b. One SIGINT (Ctrl-C) ends an srun step (srun alone wants two within a
# second), with --label putting "N: " before every line of the tasks: the
# progress tags are still taken, not shown.
"$bin/coflow" run "$cfg" --launcher srun --set run.output.dir="$out/interrupted" --set run.end_time=1000 \
  --set 'run.launch.mpi_args=[--label]' >"$out/interrupted.log" 2>&1 &
launcher=$!
for i in $(seq 1 300); do grep -q "^progress:" "$out/interrupted.log" 2>/dev/null && break; sleep 0.1; done
grep -q "^progress:" "$out/interrupted.log" || { kill "$launcher"; tail -n 20 "$out/interrupted.log"; fail "no progress line under srun --label"; }
kill -INT "$launcher"
for i in $(seq 1 100); do kill -0 "$launcher" 2>/dev/null || break; sleep 0.1; done
if kill -0 "$launcher" 2>/dev/null; then kill -9 "$launcher"; fail "the srun step still runs 10 s after one SIGINT"; fi
wait "$launcher"; rc=$?
[ "$rc" -eq 130 ] || { tail -n 20 "$out/interrupted.log"; fail "exit status $rc after SIGINT under srun, expected 130"; }
grep -q "coflow: interrupted after" "$out/interrupted.log" || fail "no interruption message under srun"
grep -q "@coflow progress" "$out/interrupted.log" && fail "raw progress lines under srun --label"
echo "one SIGINT ended the srun step (exit 130); --label prefixes did not hide the progress tags"

# 3. --launcher sbatch submits a batch job that runs the same thing with srun.
"$bin/coflow" run "$cfg" --launcher sbatch --set run.output.dir="$out/batch" --set run.end_time=0.05 >"$out/batch.log" 2>&1 \
  || { tail -n 20 "$out/batch.log"; fail "sbatch submission failed"; }
grep -q "^#SBATCH --ntasks=4$" "$out/batch/job.sbatch" || fail "job.sbatch: $(cat "$out/batch/job.sbatch")"
job=$(sed -n 's/^Submitted batch job \([0-9]*\).*/\1/p' "$out/batch.log")
[ -n "$job" ] || { cat "$out/batch.log"; fail "no job id from sbatch"; }
for i in $(seq 1 600); do squeue -h -j "$job" 2>/dev/null | grep -q . || break; sleep 0.1; done
grep -q '"status": "ok"' "$out/batch/summary.json" 2>/dev/null \
  || { cat "$out"/batch/slurm-*.out 2>/dev/null | tail -n 20; fail "the batch job did not finish ok"; }
grep -q "coflow: run 'quickstart' finished" "$out/batch/slurm-$job.out" || fail "no summary in slurm-$job.out"
echo "batch job $job ran the quickstart through srun"
echo "ok"
