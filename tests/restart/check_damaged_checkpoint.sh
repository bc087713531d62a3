#!/usr/bin/env bash
# check_damaged_checkpoint.sh BIN_DIR CONFIGS_DIR OUT
# A restart from a damaged checkpoint (a value that is not finite, a k or an
# epsilon that is not positive, a k so large that nu_t overflows, a particle's
# radius that is not positive) must stop
# before the first step with a message that names the checkpoint's file, a
# non-zero exit status and summary.json's status "failed" with the same
# reason: not run on, and not blame the step ("lower fluid.fv.cfl") or call
# it a bug. The checkpoints are damaged with Debian's h5py.
set -u
bin=$1 cfgs=$2 out=$3
trap '[ $? -ne 0 ] || "$(dirname "$0")/../clean_passed.sh" "$out"' EXIT  # a failure keeps its snapshots
rm -rf "$out"; mkdir -p "$out"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fail() { echo "FAIL: $*"; exit 1; }
# checkpointed NAME CONFIG [--set ...]: a short run that keeps its checkpoints.
checkpointed() {
  local name=$1 cfg=$2; shift 2
  "$bin/coflow" run "$cfgs/$cfg" --set run.output.dir="$out/$name" "$@" >"$out/$name.log" 2>&1 ||
    { tail -n 20 "$out/$name.log"; fail "$name: the run that writes the checkpoints failed"; }
}
first() { ls -d "$out/$1"/checkpoints/window_* | head -n 1; }
# damage FROM TO FILE DATASET INDEX VALUE: a copy of checkpoint FROM as TO,
# with the value at flat INDEX of FILE's DATASET replaced (FILE in the
# fluid's part, or a path under the checkpoint such as particles/particles.h5).
damage() {
  local from=$1 to=$2 file=$3 dataset=$4 index=$5 value=$6
  case $file in */*) ;; *) file=fluid/$file ;; esac
  rm -rf "$to"; cp -r "$from" "$to"
  /usr/bin/python3 - "$to/$file" "$dataset" "$index" "$value" <<'PY' || fail "cannot damage $to/$file"
import sys, h5py
path, name, index, value = sys.argv[1], sys.argv[2], int(sys.argv[3]), float(sys.argv[4])
with h5py.File(path, "r+") as f:
    a = f[name][...]
    a.flat[index] = value
    f[name][...] = a
PY
}
# restart NAME CONFIG CHECKPOINT MESSAGE [--set ...]
restart() {
  local name=$1 cfg=$2 ckpt=$3 msg=$4 dir="$out/$1"; shift 4
  timeout 60 "$bin/coflow" run "$cfgs/$cfg" --set run.output.dir="$dir" --restart "$ckpt" "$@" >"$dir.log" 2>&1
  local rc=$?
  [ $rc -ne 124 ] || fail "$name: hung (killed after 60 s)"
  [ $rc -ne 0 ] || fail "$name: exit status 0"
  grep -qF "$msg" "$dir.log" || { tail -n 20 "$dir.log"; fail "$name: no message '$msg' in $dir.log"; }
  grep -q '"status": "failed"' "$dir/summary.json" || fail "$name: summary.json status is not failed"
  grep -qF "$msg" "$dir/summary.json" || fail "$name: summary.json reason lacks '$msg'"
  ! grep -qE "lower fluid.fv.cfl|this is a bug" "$dir.log" || fail "$name: the message blames the step"
  echo "ok: $name: $msg"
}

# fv with k-epsilon (4 x 4 cells), and fv-reference on the same case.
ke=(--set run.end_time=1.0 --set run.checkpoint.every=0.5)
for solver in fv fv-reference; do
  checkpointed "$solver" fv_ke_decay.yaml "${ke[@]}" --set fluid.solver=$solver
done
ck=$(first fv) ckr=$(first fv-reference)
damage "$ck" "$out/nan_velocity" fv.h5 velocity_faces 7 nan
restart fv_nan_velocity fv_ke_decay.yaml "$out/nan_velocity" \
  "$out/nan_velocity/fluid/fv.h5: 'velocity_faces' holds a value that is not finite (nan) at cell (2, 0, 0), component 1: the checkpoint is damaged" \
  "${ke[@]}"
# On 2 ranks: one rank finds the value, the other is brought down with it.
restart fv_nan_velocity_2_ranks fv_ke_decay.yaml "$out/nan_velocity" \
  "fv.h5: 'velocity_faces' holds a value that is not finite (nan) at cell (2, 0, 0), component 1" \
  "${ke[@]}" --set fluid.ranks=2
damage "$ck" "$out/negative_k" fv_turbulence.h5 k 5 -1.0
restart fv_negative_k fv_ke_decay.yaml "$out/negative_k" \
  "fv: k and epsilon must be positive at t = 0.5 s (min k -1, min epsilon" "${ke[@]}"
grep -qF "$out/negative_k/fluid/fv_turbulence.h5 holds them: the checkpoint is damaged" "$out/fv_negative_k.log" ||
  fail "fv_negative_k: the message does not name the checkpoint's file"
damage "$ck" "$out/huge_k" fv_turbulence.h5 k 5 1e200
restart fv_huge_k fv_ke_decay.yaml "$out/huge_k" \
  "fv: k, epsilon or nu_t is not finite at t = 0.5 s; $out/huge_k/fluid/fv_turbulence.h5 holds them: the checkpoint is damaged" \
  "${ke[@]}"
damage "$ckr" "$out/negative_epsilon" fv_turbulence.h5 epsilon 3 0.0
restart fv_reference_negative_epsilon fv_ke_decay.yaml "$out/negative_epsilon" \
  "fv-reference: $out/negative_epsilon/fluid/fv_turbulence.h5 holds a k or an epsilon that is not positive, or a nu_t that is not finite: the checkpoint is damaged" \
  "${ke[@]}" --set fluid.solver=fv-reference

damage "$ckr" "$out/huge_k_reference" fv_turbulence.h5 k 5 1e200
restart fv_reference_huge_k fv_ke_decay.yaml "$out/huge_k_reference" \
  "fv-reference: $out/huge_k_reference/fluid/fv_turbulence.h5 holds a k or an epsilon that is not positive, or a nu_t that is not finite: the checkpoint is damaged" \
  "${ke[@]}" --set fluid.solver=fv-reference

# lbm (the plane Couette flow, 4 x 32 cells).
checkpointed lbm lbm_couette.yaml --set run.end_time=100 --set run.checkpoint.every=50
damage "$(first lbm)" "$out/inf_population" lbm.h5 populations 40 inf
restart lbm_inf_population lbm_couette.yaml "$out/inf_population" \
  "$out/inf_population/fluid/lbm.h5: 'populations' holds a value that is not finite (inf) at cell (0, 1, 0), component 4: the checkpoint is damaged" \
  --set run.end_time=100

# The particles (DEM, 5000 grains in a box): every rank reads the whole file.
dem=(--set run.end_time=2.0e-4 --set run.checkpoint.every=1.0e-4 --set run.output.every=2.0e-4)
checkpointed dem dem_ranks.yaml "${dem[@]}"
# dem_case NAME FILE DATASET INDEX VALUE MESSAGE [--set ...]: the first
# checkpoint's particles/FILE damaged, the restart refused with MESSAGE.
dem_case() {
  local name=$1 file=$2 dataset=$3 index=$4 value=$5 msg=$6; shift 6
  damage "$(first dem)" "$out/$name" "particles/$file" "$dataset" "$index" "$value"
  restart "dem_$name" dem_ranks.yaml "$out/$name" "$msg" "${dem[@]}" "$@"
}
# (The particle's id sits in the middle of some messages: their tails are
# checked after.)
dem_case nan_position particles.h5 position 11 nan "$out/nan_position/particles/particles.h5: particle" \
  --set particles.ranks=2
grep -qF "has a position that is not finite (nan): the checkpoint is damaged" "$out/dem_nan_position.log" ||
  fail "dem_nan_position: the message does not name the position"
dem_case negative_radius particles.h5 radius 4 -1.0 "has a radius that is not positive (-1): the checkpoint is damaged"
dem_case inf_shear contacts.h5 shear 0 inf "contacts.h5: particle"
grep -qF "has a contact history (tangential spring) that is not finite (inf)" "$out/dem_inf_shear.log" ||
  fail "dem_inf_shear: the message does not name the contact history"
dem_case negative_species particles.h5 species 2 -1 \
  "particles.h5: the species index -1 is not a valid whole number: the checkpoint is damaged"
dem_case nan_partner contacts.h5 partner 0 nan \
  "contacts.h5: the partner (a particle id, or -1 - a wall's index) nan is not a valid whole number"

# A parallel-explicit psm run: the load in flight that the particles keep
# (particles/hydrodynamic.csv), one of its values replaced by nan.
psm=(--set coupling.scheme=parallel-explicit --set run.end_time=0.1 --set run.checkpoint.every=0.05)
checkpointed psm psm_momentum.yaml "${psm[@]}"
rm -rf "$out/nan_load"; cp -r "$(first psm)" "$out/nan_load"
sed -i '2s/,[^,]*$/,nan/' "$out/nan_load/particles/hydrodynamic.csv"
restart psm_nan_load psm_momentum.yaml "$out/nan_load" \
  "$out/nan_load/particles/hydrodynamic.csv: the load on particle" "${psm[@]}"
grep -qF "is not finite: the checkpoint is damaged" "$out/psm_nan_load.log" || fail "psm_nan_load: no 'not finite'"
# The same file cut short to its header: the particles without a row took no
# load in the first window after the restart (before 2026-12-05).
rm -rf "$out/short_load"; cp -r "$(first psm)" "$out/short_load"
sed -i '2,$d' "$out/short_load/particles/hydrodynamic.csv"
restart psm_short_load psm_momentum.yaml "$out/short_load" \
  "$out/short_load/particles/hydrodynamic.csv: 0 rows, 0 of them for the checkpoint's" "${psm[@]}"

# fv on the adaptive grid (the vortex on 3 levels): the flow's face velocities.
checkpointed amr fv_amr_vortex.yaml --set run.end_time=0.04 --set run.checkpoint.every=0.02
damage "$(first amr)" "$out/nan_mac" flow.h5 mac 10 nan
restart amr_nan_mac fv_amr_vortex.yaml "$out/nan_mac" \
  "refinement: $out/nan_mac/fluid/flow.h5 holds a value that is not finite in 'mac': the checkpoint is damaged" \
  --set run.end_time=0.04
# Its clock (amr.txt: steps, time and last step as hexadecimal floats): a
# time that is not a number was read as 0 before 2026-12-05.
rm -rf "$out/amr_time"; cp -r "$(first amr)" "$out/amr_time"
sed -i '1s/^\([0-9]*\) [^ ]*/\1 0xzz/' "$out/amr_time/fluid/amr.txt"
restart amr_bad_time fv_amr_vortex.yaml "$out/amr_time" \
  "refinement): $out/amr_time/fluid/amr.txt holds a time 0xzz or a last step" --set run.end_time=0.04

# Its forest cut short (a disk that filled while it was written): p4est
# aborts on the file, which now stops the run with a reason (before
# 2026-12-07 its default abort raised SIGABRT, and no component said why).
rm -rf "$out/amr_short"; cp -r "$(first amr)" "$out/amr_short"
truncate -s 200 "$out/amr_short/fluid/forest.p4est"
restart amr_short_forest fv_amr_vortex.yaml "$out/amr_short" \
  "refinement: p4est stopped on the error printed above it in this component's output" --set run.end_time=0.04

# fv on the adaptive grid with k-epsilon (homogeneous decay on 2 levels): the
# forest's k. The p4est file holds the cells' values as raw doubles; the bits
# of one k are taken from the snapshot written with the checkpoint (t = 0.1)
# and every copy of them replaced.
amrke=(--set run.end_time=0.2 --set run.checkpoint.every=0.1 --set run.output.every=0.1)
checkpointed amr_ke fv_amr_ke_decay.yaml "${amrke[@]}"
for case in k:-1.0 k:1e200 nu_t:-1.0; do
  field=${case%%:*} value=${case#*:} to="$out/amr_${case/:/_}"
  rm -rf "$to"; cp -r "$(first amr_ke)" "$to"
  /usr/bin/python3 - "$out/amr_ke/fluid/step_000001_levels.h5" "$to/fluid/forest.p4est" "$field" "$value" <<'PY' ||
import struct, sys, h5py
q = float(h5py.File(sys.argv[1], "r")["level0_" + sys.argv[3]][0, 0])
old, new = struct.pack("<d", q), struct.pack("<d", float(sys.argv[4]))
data = open(sys.argv[2], "rb").read()
if data.count(old) == 0:
    sys.exit("the snapshot's " + sys.argv[3] + " is not in the forest's file")
open(sys.argv[2], "wb").write(data.replace(old, new))
PY
    fail "cannot damage $to/fluid/forest.p4est"
done
message="fv (refinement): k and epsilon must be positive, C_mu k^2 / epsilon finite and nu_t finite and not negative in"
restart amr_negative_k fv_amr_ke_decay.yaml "$out/amr_k_-1.0" \
  "$message $out/amr_k_-1.0/fluid/forest.p4est (min k -1," "${amrke[@]}"
restart amr_huge_k fv_amr_ke_decay.yaml "$out/amr_k_1e200" "$message $out/amr_k_1e200/fluid/forest.p4est" "${amrke[@]}"
restart amr_negative_nu_t fv_amr_ke_decay.yaml "$out/amr_nu_t_-1.0" \
  "$message $out/amr_nu_t_-1.0/fluid/forest.p4est" "${amrke[@]}"
echo "ok"
