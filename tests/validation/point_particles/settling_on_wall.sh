#!/usr/bin/env bash
# settling_on_wall.sh BIN_DIR CONFIG OUT
# The case of settling_on_wall.yaml must either run to its end or stop naming
# the cause: point particles resting on the z- wall whose momentum source
# drives the flow (a warning first, at Mach 0.1, then the error); and with the
# remedy it names (an outlet on that face) it must run to its end.
set -u
bin=$1 cfg=$2 out=$3
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
rm -rf "$out"; mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
if "$bin/coflow" run "$cfg" --set run.output.dir="$out/run" >"$out/run.log" 2>&1; then
  echo "the case ran to its end"
else
  grep -q "run failed in component 'fluid'" "$out/run.log" || { tail -n 5 "$out/run.log"; fail "no fluid failure reported"; }
  for text in "momentum source reaches" "next to the z- wall" "no resting contact" "particles.coupling: one-way"; do
    grep "run failed" "$out/run.log" | grep -q "$text" || { grep "run failed" "$out/run.log"; fail "the error does not say '$text'"; }
  done
  cat "$out"/run/logs/fluid*.log | grep "warning" | grep -q "next to the z- wall" || fail "no earlier warning names the cause"
  echo "stopped naming the cause: $(grep "run failed" "$out/run.log" | grep -o "Mach number [0-9.]* at step [0-9]*"), warned $(cat "$out"/run/logs/fluid*.log | grep -o 'Mach number [0-9.]* at step [0-9]*' | head -1)"
fi
"$bin/coflow" run "$cfg" --set run.output.dir="$out/outlet" --set particles.boundaries.z-=outlet >"$out/outlet.log" 2>&1 ||
  { tail -n 5 "$out/outlet.log"; fail "the remedy (an outlet on z-) did not run to the end"; }
last=$(tail -n 1 "$out/outlet/series/fluid.csv" | cut -d, -f1)
echo "with particles.boundaries.z-: outlet the case ran to t = $last s"
