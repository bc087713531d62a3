#!/usr/bin/env bash
# tutorial.sh BIN_DIR TUTORIAL_DIR OUT
# Steps 2 and 3 of docs/tutorial.md run to their end with grains in flight,
# and step 3 with a wall under the grains stops naming the cause, as the
# tutorial says.
set -u
bin=$1 dir=$2 out=$3
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
rm -rf "$out"; mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
for step in 2_particles 3_coupled; do
  "$bin/coflow" run "$dir/$step.yaml" --set run.output.dir="$out/$step" >"$out/$step.log" 2>&1 ||
    { tail -n 5 "$out/$step.log"; fail "$step did not run"; }
  row=$(tail -n 1 "$out/$step/series/particles.csv")
  [ "$(echo "$row" | cut -d, -f1)" = 2 ] || fail "$step ended at $(echo "$row" | cut -d, -f1), not 2 s"
  [ "$(echo "$row" | cut -d, -f2)" -gt 0 ] || fail "$step has no grains in flight"
  echo "$step: $(echo "$row" | cut -d, -f2) grains in flight at t = 2 s"
  # Snapshots at exactly the multiples of run.output.every (0.5 s), fluid and particles.
  for comp in fluid particles; do
    times=$(tail -n +2 "$out/$step/$comp/index.csv" | cut -d, -f1,2 | tr '\n' ' ')
    [ "$times" = "0,0 1,0.5 2,1 3,1.5 4,2 " ] || fail "$step: $comp snapshots (number,time): $times"
  done
done
grep -q "two-way" "$out/3_coupled/logs/immersed.log" || fail "step 3 does not log two-way coupling"
"$bin/coflow" run "$dir/3_coupled.yaml" --set run.output.dir="$out/wall" --set particles.boundaries.z-=wall \
  >"$out/wall.log" 2>&1 && fail "step 3 with a wall under the grains ran to its end"
grep "run failed" "$out/wall.log" | grep -q "next to the z- wall" || fail "step 3 with a wall did not name the cause"
echo "step 3 with a wall under the grains stops naming the cause"
