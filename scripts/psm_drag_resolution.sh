#!/usr/bin/env bash
# Resolution study of the psm drag on a simple cubic array (issue 6): the
# Zick & Homsy cases at phi 0.064 and 0.125 on grids of 16 to 48 cells per
# periodic box (the sphere 8 to 30 cells across), tau = 1, the physical case
# unchanged. Writes OUT/resolution.csv and docs/img/psm_drag_resolution.png.
#
#   scripts/psm_drag_resolution.sh [OUT]      (OUT defaults to out/drag-resolution)
#
# About 15 minutes on 2 cores (the 48-cell runs take most of it).
set -eu
cd "$(dirname "$0")/.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
out=${1:-out/drag-resolution}
mkdir -p "$out"
csv=$out/resolution.csv
echo "phi,cells,diameter_cells,K,K_zick_homsy,error,settling" > "$csv"
for cfg in configs/validation/psm_drag_array.yaml configs/cases/psm_drag_array_phi0125.yaml; do
  for n in 16 24 32 48; do
    dir=$out/$(basename "$cfg" .yaml)-$n
    grep -qs '"status": "ok"' "$dir/summary.json" ||  # finished runs are kept: the study can be resumed
      build/bin/coflow run "$cfg" --set run.output.dir="$dir" --set "domain.cells=[$n,$n,$n]" \
        --set run.output.every=100.0 > "$dir.log" 2>&1
    m=$(build/bin/coflow-check drag "$dir")
    get() { echo "$m" | sed -n "s/^$1=//p"; }
    d=$(awk -v n="$n" -v phi="$(get phi)" 'BEGIN { printf "%.2f", n * (6 * phi / 3.141592653589793) ^ (1 / 3) }')
    err=$(awk -v k="$(get K)" -v r="$(get K_zick_homsy)" 'BEGIN { printf "%.5f", k / r - 1 }')
    echo "$(get phi),$n,$d,$(get K),$(get K_zick_homsy),$err,$(get settling)" | tee -a "$csv"
  done
done
/usr/bin/python3 scripts/plot_drag_resolution.py "$csv" docs/img/psm_drag_resolution.png
