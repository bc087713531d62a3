#!/usr/bin/env bash
# Runs the granular jet on a plate (seed 003 §5.3) for the opening (spread)
# angles 0/5/10/15 degrees at a nozzle angle of 90 degrees, and for the nozzle
# angles 30/45/60 degrees without spread, from configs/cases/dpm_jet_plate.yaml
# (0.05 s), then draws the impact maps (scripts/plot_jet_impacts.py).
#   scripts/jet_plate_cases.sh [OUT_DIR=out/jet-plate] [END_TIME=0.05]
# The nozzle of angle Phi points along [cos Phi, -sin Phi, 0] from 0.1 m before
# the plate's centre (0.1, 0.05, 0.1), as in seed 003 eq. 5.20.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-out/jet-plate}; end=${2:-0.05}
mkdir -p "$out"
plate="$root/configs/cases/geometry/jet_plate.stl"
[ -f "$plate" ] || /usr/bin/python3 "$root/scripts/make_plate_stl.py" "$plate"
run() {  # NAME PHI SPREAD [--set ...]
  local name=$1 phi=$2 spread=$3; shift 3
  local dir dx dy cx cy
  dir=$(/usr/bin/python3 -c "import math; p=math.radians($phi); print(f'[{math.cos(p):.12f}, {-math.sin(p):.12f}, 0.0]')")
  cx=$(/usr/bin/python3 -c "import math; print(f'{0.1 - 0.1 * math.cos(math.radians($phi)):.12f}')")
  cy=$(/usr/bin/python3 -c "import math; print(f'{0.05 + 0.1 * math.sin(math.radians($phi)):.12f}')")
  "$root/build/bin/coflow" run "$root/configs/cases/dpm_jet_plate.yaml" --set run.output.dir="$out/$name" \
    --set run.end_time="$end" \
    --set "particles.injection=[{species: grain, mass_flow: 0.025758, speed: 20.0, spread_angle: $spread, direction: $dir, disk: {center: [$cx, $cy, 0.1], normal: $dir, diameter: 4.8e-3}}]" \
    "$@" > "$out/$name.log" 2>&1
  echo "$name: $("$root/build/bin/coflow-check" jet "$out/$name" | tr '\n' ' ')"
}
run no_pp 90 0 --set particles.collision.enabled=false
for s in 0 5 10 15; do run spread_$s 90 "$s"; done
for p in 30 45 60; do run nozzle_$p "$p" 0; done
/usr/bin/python3 "$root/scripts/plot_jet_impacts.py" "$out"
