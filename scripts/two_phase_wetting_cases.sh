#!/usr/bin/env bash
# Contact angle against the angle asked for (issue 20): a red half-disc of 25
# cells on the wall of a 240 x 60 box (configs/validation/two_phase_contact_angle.yaml,
# widened so that a spread drop stays clear of its periodic images), 10^4
# steps, at 30, 45, 60, 90, 120, 135 and 150 degrees, with the geometric
# wetting (the default) and the seed's fixed solid colour. Writes
# OUT/wetting.csv and docs/img/two_phase_wetting.png.
#
#   scripts/two_phase_wetting_cases.sh [OUT]   (OUT defaults to out/two-phase-wetting)
#
# About 6 minutes on 2 cores.
set -eu
cd "$(dirname "$0")/.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
out=${1:-out/two-phase-wetting}
mkdir -p "$out"
csv=$out/wetting.csv
echo "wetting,asked,measured,steps" > "$csv"
for wetting in geometric seed; do
  for angle in 30 45 60 90 120 135 150; do
    dir=$out/$wetting-$angle
    grep -qs '"status": "ok"' "$dir/summary.json" ||  # finished runs are kept: the study can be resumed
      build/bin/coflow run configs/validation/two_phase_contact_angle.yaml --set run.output.dir="$dir" \
        --set domain.cells=[240,60,1] --set domain.upper=[0.24,0.06,0.001] \
        --set "fluid.initial.phase=[{fill: {phase: blue}}, {sphere: {centre: [0.12, 0.0, 0.0005], radius: 0.025, phase: red}}]" \
        --set fluid.two_phase.wetting=$wetting --set fluid.two_phase.contact_angle=$angle > "$dir.log" 2>&1
    m=$(build/bin/coflow-check contact_angle "$dir")
    echo "$wetting,$angle,$(echo "$m" | sed -n 's/^contact_angle=//p'),10000" | tee -a "$csv"
  done
done
/usr/bin/python3 scripts/plot_wetting.py "$csv" docs/img/two_phase_wetting.png
