#!/usr/bin/env bash
# check_launcher.sh BIN_DIR CONFIG_DIR
# The launcher's command line: the exact MPMD line of --dry-run, the srun
# multi-prog file, `coflow variants`, and exit codes.
set -u
bin=$1 cfgs=$2
status=0
fail() { echo "FAIL: $*"; status=1; }
cd "$(mktemp -d)"
cfg=$cfgs/tests/coupler_dummies.yaml

# 6 ranks on this machine: oversubscribed when they exceed the cores; then
# run.launch.bind auto pins them (each core shared by several), unless
# COFLOW_BIND (scripts/test: none) says otherwise.
unset COFLOW_BIND
# Open MPI's slots: the physical cores of this process's CPUs (not threads).
cores=$(/usr/bin/python3 -c 'import os
t = "/sys/devices/system/cpu/cpu%d/topology/"
print(len({(open(t % c + "physical_package_id").read(), open(t % c + "core_id").read()) for c in os.sched_getaffinity(0)}))' 2>/dev/null || nproc)
over=""; [ 6 -gt "$cores" ] && over="--oversubscribe --bind-to core:overload-allowed "
want="mpirun ${over}-np 2 $bin/coflow-fluid out/coupler-dummies/config.yaml : -np 3 $bin/coflow-immersed out/coupler-dummies/config.yaml : -np 1 $bin/coflow-particles out/coupler-dummies/config.yaml"
got=$("$bin/coflow" run --dry-run "$cfg")
[ "$got" = "$want" ] || fail "dry-run line
  want: $want
  got:  $got"
[ ! -e out ] || fail "--dry-run created files"

got=$("$bin/coflow" run --dry-run --set run.launch.bind=none --set 'run.launch.mpi_args=[--mca, btl, self]' "$cfg")
case "$got" in "mpirun "*"--bind-to none --mca btl self -np 2 "*) ;; *) fail "bind none and mpi_args: $got" ;; esac
got=$(COFLOW_BIND=none "$bin/coflow" run --dry-run "$cfg")
[ 6 -le "$cores" ] || case "$got" in *"--bind-to none -np 2 "*) ;; *) fail "COFLOW_BIND=none: $got" ;; esac
got=$(COFLOW_BIND=none "$bin/coflow" run --dry-run --set run.launch.bind=core "$cfg")
case "$got" in *"--bind-to core"*) ;; *) fail "run.launch.bind core over COFLOW_BIND: $got" ;; esac
"$bin/coflow" run --dry-run --set run.launch.bind=sockets "$cfg" >/dev/null 2>&1; rc=$?
[ $rc -eq 2 ] || fail "run.launch.bind sockets: exit $rc, expected 2"

# External variants (the dummies' configuration) without --exe: exit 2 with
# the file's place, before any rank starts (--dry-run above prints the line).
msg=$("$bin/coflow" run "$cfg" 2>&1); rc=$?
[ $rc -eq 2 ] || fail "external without --exe: exit $rc, expected 2"
case "$msg" in *"$cfg:16:11: fluid.solver: 'external' runs your own executable: give it with --exe fluid=PATH"*) ;;
  *) fail "external without --exe: $msg" ;; esac
[ ! -e out ] || fail "external without --exe: a run directory was made"
# The same from --set: the file's solver line is not the one to name.
msg=$("$bin/coflow" run --set fluid.solver=external --set run.output.dir=out-external "$cfgs/quickstart.yaml" 2>&1); rc=$?
[ $rc -eq 2 ] || fail "--set fluid.solver=external without --exe: exit $rc, expected 2"
case "$msg" in "$cfgs/quickstart.yaml: fluid.solver: 'external' runs your own executable"*) ;;
  *) fail "--set external without --exe: $msg" ;; esac
[ ! -e out-external ] || fail "--set external without --exe: a run directory was made"

# The configuration is the run directory's own config.yaml (a run rewrites
# it with the resolved one): exit 2, the file untouched. A user's config.yaml
# alone does not make a directory a run's: refused at validation.
mkdir -p mine && cp "$cfgs/quickstart.yaml" mine/config.yaml
msg=$("$bin/coflow" run mine/config.yaml --set run.output.dir=mine 2>&1); rc=$?
[ $rc -eq 2 ] || fail "a directory holding only the user's config.yaml: exit $rc, expected 2"
case "$msg" in *"run.output.dir: 'mine' holds files and is not a coflow run directory"*) ;; *) fail "mine: $msg" ;; esac
: >mine/summary.json
msg=$("$bin/coflow" run mine/config.yaml --set run.output.dir=mine 2>&1); rc=$?
[ $rc -eq 2 ] || fail "the configuration is the run directory's config.yaml: exit $rc, expected 2"
case "$msg" in *"the configuration is the run directory's config.yaml"*) ;; *) fail "mine/config.yaml: $msg" ;; esac
cmp -s "$cfgs/quickstart.yaml" mine/config.yaml || fail "the user's config.yaml was rewritten"

# --exe of a file that is not executable: exit 2 before any rank starts.
echo "not a program" >plain.txt
msg=$("$bin/coflow" run "$cfg" --exe fluid=plain.txt 2>&1); rc=$?
[ $rc -eq 2 ] || fail "--exe of a plain file: exit $rc, expected 2"
case "$msg" in *"--exe fluid=plain.txt: not an executable file"*) ;; *) fail "--exe of a plain file: $msg" ;; esac

# --exe for a component the configuration does not have: exit 2.
msg=$("$bin/coflow" run "$cfgs/validation/lbm_couette.yaml" --exe particles="$bin/coflow-dummy-particles" 2>&1); rc=$?
[ $rc -eq 2 ] || fail "--exe of a component not in the configuration: exit $rc, expected 2"
case "$msg" in *"has no particles section, so nothing would run it"*) ;; *) fail "--exe particles: $msg" ;; esac

# A run directory in use by another run (its launcher holds .coflow.lock):
# exit 2, and the directory is left alone.
mkdir -p busy && echo keep >busy/mine.txt && : >busy/.coflow.lock
msg=$(flock busy/.coflow.lock "$bin/coflow" run "$cfgs/quickstart.yaml" --set run.output.dir=busy 2>&1); rc=$?
[ $rc -eq 2 ] || fail "a run directory in use: exit $rc, expected 2"
case "$msg" in *"busy is in use by another coflow run"*) ;; *) fail "a run directory in use: $msg" ;; esac
[ -f busy/mine.txt ] && [ ! -e busy/fluid ] || fail "a run directory in use was changed"

mkdir -p ckpt && echo "window: 3" >ckpt/checkpoint.yaml
got=$("$bin/coflow" run --dry-run --set fluid.ranks=1 --set run.output.dir=o --restart ckpt "$cfg" | head -n 1)
case "$got" in *"-np 1 $bin/coflow-fluid o/config.yaml --restart $PWD/ckpt"*) ;; *) fail "--set/--restart not in the line: $got" ;; esac
"$bin/coflow" run --dry-run --restart . "$cfg" >/dev/null 2>&1; rc=$?
[ $rc -eq 2 ] || fail "--restart of a directory without checkpoint.yaml: exit $rc, expected 2"

got=$(SLURM_JOB_CPUS_PER_NODE=2 "$bin/coflow" run --dry-run --launcher srun "$cfg")  # 6 ranks on 2 CPUs: --overcommit
printf '%s\n' "$got" | head -n 1 | grep -qx "srun --mpi=pmix --kill-on-bad-exit=1 --quit-on-interrupt -n 6 --overcommit --multi-prog out/coupler-dummies/multi-prog.conf" || fail "srun line: $got"
got2=$(SLURM_JOB_CPUS_PER_NODE=2 "$bin/coflow" run --dry-run --launcher srun --set run.launch.bind=core --set 'run.launch.mpi_args=[--exclusive]' "$cfg")
printf '%s\n' "$got2" | head -n 1 | grep -qx "srun --mpi=pmix --kill-on-bad-exit=1 --quit-on-interrupt -n 6 --overcommit --cpu-bind=cores --exclusive --multi-prog out/coupler-dummies/multi-prog.conf" || fail "srun line with bind and mpi_args: $got2"
printf '%s\n' "$got" | grep -qx "0-1 $bin/coflow-fluid out/coupler-dummies/config.yaml" || fail "multi-prog fluid line"
printf '%s\n' "$got" | grep -qx "2-4 $bin/coflow-immersed out/coupler-dummies/config.yaml" || fail "multi-prog immersed line"
printf '%s\n' "$got" | grep -qx "5-5 $bin/coflow-particles out/coupler-dummies/config.yaml" || fail "multi-prog particles line"
# 6 ranks in an allocation of two nodes of 4 CPUs: no --overcommit.
got=$(SLURM_JOB_CPUS_PER_NODE='4(x2)' "$bin/coflow" run --dry-run --launcher srun "$cfg")
printf '%s\n' "$got" | head -n 1 | grep -qx "srun --mpi=pmix --kill-on-bad-exit=1 --quit-on-interrupt -n 6 --multi-prog out/coupler-dummies/multi-prog.conf" || fail "srun line in 4(x2) CPUs: $got"
# srun's --output/-o/--error/-e in run.launch.mpi_args (also --out=, -ofile):
# the launcher would read no output; exit 2 under srun and sbatch, before any
# rank starts, at the file's place. mpirun keeps them (its own options).
for a in --output=ranks.txt --ou=ranks.txt -ofile -e -lo -lvefile; do
  msg=$("$bin/coflow" run --dry-run --launcher srun --set "run.launch.mpi_args=[--label, $a]" "$cfg" 2>&1); rc=$?
  [ $rc -eq 2 ] || fail "srun with mpi_args $a: exit $rc, expected 2"
  case "$msg" in *"run.launch.mpi_args: '$a' sends the components' output to files under srun"*) ;;
    *) fail "srun with mpi_args $a: $msg" ;; esac
done
sed 's/^run:$/run:\n  launch: {mpi_args: [--label, --error=err.txt]}/' "$cfg" >srun_error.yaml
msg=$("$bin/coflow" run --launcher sbatch --dry-run srun_error.yaml 2>&1); rc=$?
[ $rc -eq 2 ] || fail "sbatch with mpi_args --error: exit $rc, expected 2"
case "$msg" in "srun_error.yaml:6:32: run.launch.mpi_args: '--error=err.txt'"*) ;; *) fail "sbatch --error place: $msg" ;; esac
# A bad value from --set names the --set, not a place in the file (the
# value's own node said 1:1); a problem elsewhere keeps the file's place.
msg=$("$bin/coflow" run --dry-run --set run.end_time=-1 "$cfg" 2>&1); rc=$?
[ $rc -eq 2 ] || fail "--set run.end_time=-1: exit $rc, expected 2"
case "$msg" in "$cfg: run.end_time: must be > 0 (got -1) (from --set run.end_time=-1)") ;;
  *) fail "--set place: $msg" ;; esac
# A section the --set made (not in the file) is named the same way (it took
# the place of the enclosing section's first key).
msg=$("$bin/coflow" run --dry-run --set immersed.psmx.refinement=3 "$cfgs/quickstart.yaml" 2>&1); rc=$?
[ $rc -eq 2 ] || fail "--set immersed.psmx.refinement=3: exit $rc, expected 2"
case "$msg" in *"$cfgs/quickstart.yaml: immersed.psmx: unknown key 'psmx'"*"(from --set immersed.psmx.refinement=3)"*) ;;
  *) fail "--set of a new section: $msg" ;; esac
# A --set list replaces the file's: no place in the file (it would name the
# file's own item).
msg=$("$bin/coflow" run --launcher srun --dry-run --set 'run.launch.mpi_args=[--exclusive, -o, x]' srun_error.yaml 2>&1)
case "$msg" in "srun_error.yaml: run.launch.mpi_args: '-o'"*) ;; *) fail "srun -o from --set: $msg" ;; esac
"$bin/coflow" run --launcher srun --dry-run --set 'run.launch.mpi_args=[--exclusive, --export=ALL, --overlap, -O]' \
  "$cfg" >/dev/null 2>&1 || fail "srun options that start with e or o were refused"
msg=$("$bin/coflow" run --launcher srun --dry-run --set 'run.launch.mpi_args=[-lpoutput, -Joe, -J, -lo]' "$cfg" 2>&1) ||
  fail "srun's -p/-J with an argument holding o or e were refused: $msg"
"$bin/coflow" run --dry-run --set 'run.launch.mpi_args=[--output-filename, o]' "$cfg" >/dev/null ||
  fail "mpirun with --output-filename refused"
# srun splits a --multi-prog line at spaces and reads quotes and %: each
# character outside [A-Za-z0-9_./=:,+@-] of a path goes behind a backslash.
got=$(SLURM_JOB_CPUS_PER_NODE=8 "$bin/coflow" run --dry-run --launcher srun --set "run.output.dir=o u%t's" "$cfg")
printf '%s\n' "$got" | grep -qxF "0-1 $bin/coflow-fluid o\\ u\\%t\\'s/config.yaml" || fail "multi-prog line of a path with a space, % and a quote: $got"

# --launcher sbatch --dry-run: the batch script, tasks and a time limit from
# the pre-run report (the quickstart's lbm estimates; x 1.5 + 10 min).
got=$("$bin/coflow" run --dry-run --launcher sbatch --set fluid.ranks=4 "$cfgs/quickstart.yaml")
printf '%s\n' "$got" | grep -qx "#SBATCH --ntasks=6" || fail "sbatch script tasks: $got"
printf '%s\n' "$got" | grep -q "^#SBATCH --time=00:1[0-9]:00   # the pre-run report's estimate" || fail "sbatch time limit: $got"
printf '%s\n' "$got" | grep -q "^exec $bin/coflow run $cfgs/quickstart.yaml --launcher srun --set fluid.ranks=4$" \
  || fail "sbatch command: $got"
# fv and dem estimate their wall time too (before 2026-12-07 only lbm did, and
# these got 1 h): the cavity about 11 s, the pour about 16 s, so 11 min each.
for c in validation/fv_cavity_re100.yaml validation/dem_gravity_pour.yaml; do
  got=$("$bin/coflow" run --dry-run --launcher sbatch "$cfgs/$c")
  printf '%s\n' "$got" | grep -q "^#SBATCH --time=00:1[0-9]:00   # the pre-run report's estimate" ||
    fail "sbatch time limit of $c: $got"
done
got=$("$bin/coflow" run --dry-run --launcher sbatch --set "run.output.dir=my run%" "$cfgs/quickstart.yaml")
printf '%s\n' "$got" | grep -qxF "#SBATCH --output=\"$PWD/my run%%/slurm-%j.out\"" || fail "sbatch --output of a path with a space and %: $got"
[ ! -e out ] || fail "--dry-run --launcher sbatch created files"

vars=$("$bin/coflow" variants)
for v in lbm lbm-reference analytic; do printf '%s\n' "$vars" | grep -qE "^  $v " || fail "variants lacks $v"; done
printf '%s\n' "$vars" | grep -q "fluid.lbm.tau" || fail "variants lacks the options of lbm"

"$bin/coflow" validate "$cfgs/quickstart.yaml" >/dev/null || fail "quickstart does not validate"
"$bin/coflow" run --dry-run "$cfgs/quickstart.yaml" --set fluid.lbm.tau=0.4 >/dev/null 2>&1; rc=$?
[ $rc -eq 2 ] || fail "bad --set value: exit $rc, expected 2"
"$bin/coflow" run --dry-run --exe fluid=/nonexistent "$cfg" >/dev/null 2>&1; rc=$?
[ $rc -eq 2 ] || fail "missing --exe file: exit $rc, expected 2"
# A run directory that cannot be made: a message and exit 1, not an abort.
msg=$("$bin/coflow" run "$cfgs/quickstart.yaml" --set run.output.dir=/proc/coflow-no-such-dir 2>&1); rc=$?
[ $rc -eq 1 ] || fail "unwritable run.output.dir: exit $rc, expected 1: $msg"
printf '%s\n' "$msg" | grep -q "^coflow: .*/proc/coflow-no-such-dir" || fail "unwritable run.output.dir: message: $msg"
"$bin/coflow" frobnicate >/dev/null 2>&1; rc=$?
[ $rc -eq 2 ] || fail "unknown subcommand: exit $rc, expected 2"
[ $status -eq 0 ] && echo "launcher checks passed"
exit $status
