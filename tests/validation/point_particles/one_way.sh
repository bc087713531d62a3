#!/usr/bin/env bash
# one_way.sh BIN_DIR CONFIG OUT: point particles with particles.coupling: one-way.
# The fluid must not feel them: it starts at rest in a periodic box with no
# force, so its momentum stays exactly 0 in every row (conservation, no
# source); the particles still feel the fluid (drag slows them: the last row's
# momentum is below the first's), and the immersed series still reports the
# force on them.
set -u
bin=$1 cfg=$2 out=$3
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
rm -rf "$out"
"$bin/coflow" run "$cfg" --set run.output.dir="$out" --set particles.coupling=one-way >"$out.log" 2>&1 ||
  { tail -n 20 "$out.log"; echo "FAIL: run"; exit 1; }
grep -q "one-way coupling (particles.coupling: one-way)" "$out/logs/immersed.log" || { echo "FAIL: no one-way line in the log"; exit 1; }
awk -F, 'NR > 1 && !/^#/ && ($3 != 0 || $4 != 0 || $5 != 0) { print "FAIL: fluid momentum " $3 ", " $4 ", " $5 " at t = " $1; bad = 1 }
         END { exit bad }' "$out/series/fluid.csv" || exit 1
awk -F, 'NR == 3 { p0 = $3 } { p = $3 } END { if (!(p < p0 && p > 0)) { print "FAIL: particle momentum " p0 " -> " p; exit 1 } }' \
  "$out/series/particles.csv" || exit 1
awk -F, 'NR > 3 && $2 == 0 { zero++ } END { if (zero > 0) { print "FAIL: immersed force 0 in " zero " rows"; exit 1 } }' \
  "$out/series/immersed.csv" || exit 1
echo "one-way: fluid momentum exactly 0 in every row; particles slowed by drag; immersed force reported: ok"
