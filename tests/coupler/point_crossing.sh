#!/usr/bin/env bash
# point_crossing.sh BIN_DIR CONFIG OUT
# The point method samples the fluid once a window: particles that cross
# more than a fluid cell in one window are warned about (once), with the
# window that keeps them within a cell; a run within a cell gets no warning.
# CONFIG: configs/validation/dpm_two_way_loaded.yaml (0.1 m/s, cells of 1 cm,
# lattice step 0.010015 s).
set -u
bin=$1 cfg=$2 out=$3
rm -rf "$out"; mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
# 15 lattice steps a window: 0.1 m/s x 0.15 s is 1.5 cells (the particles slow
# to 0.083 m/s in the first window: 1.25 cells).
# Ten such windows (a given window must divide run.end_time).
"$bin/coflow" run "$cfg" --set run.output.dir="$out/fast" --set coupling.window=0.15022032314060624 \
  --set run.end_time=1.5022032314060624 --set run.output.every=1.5022032314060624 \
  --set run.output.series_every=1.5022032314060624 >"$out/fast.log" 2>&1 || { tail -n 20 "$out/fast.log"; fail "the run failed"; }
n=$(grep -c "particles cross up to 1.25 fluid cells in one coupling window" "$out/fast.log")
[ "$n" -eq 1 ] || fail "expected one warning on crossing 1.25 cells, got $n"
grep -q "a coupling.window of at most 0.12 s keeps them within a cell" "$out/fast.log" || fail "no advice on the window"
"$bin/coflow" run "$cfg" --set run.output.dir="$out/slow" >"$out/slow.log" 2>&1 || fail "the default run failed"
grep -q "particles cross up to" "$out/slow.log" && fail "a warning where the particles stay within a cell"
echo "ok: one warning at 1.25 cells a window, none at 0.1"
