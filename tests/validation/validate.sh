#!/usr/bin/env bash
# Generic validation driver.
#   validate.sh CASE BIN_DIR OUT MODE CONFIG [ARGS...]
# MODE:
#   profile|decay|mass|ramp|...  run CONFIG once (ARGS: --set overrides), then coflow-check MODE
#   MODE+MODE...        one run as above, then coflow-check with each MODE
#   compare             ARGS: "A overrides" "B overrides" (each a space-separated list
#                       of key=value; a first item config=FILE runs FILE, a file
#                       beside CONFIG, instead); runs both and compares the last snapshots
#                       and the event logs (events/*.csv) when the runs write them
#   layouts             as compare; run A must log the packed population layout and
#                       run B the spaced one (lbm)
#   reflection          ARGS: three override lists (open face, long box, other open
#                       face); coflow-check outflow_reflection of runs 1 and 3 against 2
#   pair                ARGS: a coflow-check mode, two override lists; runs
#                       both, then that mode on the two runs (ibm_frames,
#                       ibm_extrapolated)
#   order               ARGS: three override lists (coarse, medium, fine);
#                       prints l2 errors and the observed orders of convergence
#   order_tg            as order, for the Taylor-Green vortex (coflow-check tg_error)
#   order_time          ARGS: four override lists (step dt, dt/2, dt/4, dt/8 on one
#                       grid); the differences of successive runs' last snapshots
#                       (coflow-check compare) and the observed orders in time
#   damping             ARGS: local damping values; runs the impact per value and
#                       checks that the restitution decreases
#   formulations        runs CONFIG with fluid.lbm.formulation standard and
#                       incompressible; prints both profile errors and their ratio
#   address_limit       ARGS: a limit (KiB) on address space; runs CONFIG with
#                       and without it and compares (lbm's layout fallback)
#   openfoam_backward_step  ARGS: NX NY ITERATIONS T1 T2, then --set overrides:
#                       the step on NX x NY cells (to T1, and restarted from
#                       there to T2; T1 a multiple of T2 - T1) against
#                       OpenFOAM's simpleFoam with the same model
#                       (scripts/openfoam_backward_step.sh); exit 77 (skipped)
#                       without OpenFOAM
#   restart_from        ARGS: EVERY, "A overrides", "B overrides": run B straight,
#                       run A with a checkpoint every EVERY seconds, restart B from
#                       A's first checkpoint; compares B restarted with B straight
#                       (variants that share a checkpoint format), and its event
#                       logs' rows with the straight run's last ones
# Every metric printed is checked against the rows of references.csv whose first
# column is CASE: `case,metric,op,bound,source`.
set -u -o pipefail
case_name=$1 bin=$2 out=$3 mode=$4 cfg=$5; shift 5
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"
metrics="$out/metrics.txt"; : >"$metrics"

run() {  # run DIR [--set ...]; a first argument config=FILE (from an override list) runs FILE instead
  local dir=$1 file=$cfg; shift
  if [ "${1:-}" = --set ] && [[ "${2:-}" == config=* ]]; then file=$(dirname "$cfg")/${2#config=}; shift 2; fi
  rm -rf "$dir"
  if ! "$bin/coflow" run "$file" --set run.output.dir="$dir" "$@" >"$dir.log" 2>&1; then
    tail -n 20 "$dir.log"; echo "FAIL: run failed ($dir)"; exit 1
  fi
}
sets() {  # "a=1 b=2" -> --set a=1 --set b=2
  local kv; for kv in $1; do printf -- '--set\n%s\n' "$kv"; done
}
check() { "$bin/coflow-check" "$@" || { echo "FAIL: coflow-check $*"; exit 1; }; }
# series_difference NAME: series/NAME.csv of runs a and b, when both write it
# with more than a time column: prints series_NAME_difference, the largest
# difference of a value relative to the larger of the two (0 when both are 0),
# or "nan" (fails a reference row) for a NaN or another row count.
series_difference() {
  local fa="$out/a/series/$1.csv" fb="$out/b/series/$1.csv"
  [ -f "$fa" ] && [ -f "$fb" ] && [ "$(head -n 1 "$fa" | tr -cd , | wc -c)" -gt 0 ] || return 0
  awk -F, -v name="$1" 'FNR <= 2 { next } FNR == NR { a[FNR] = $0; na = FNR; next }
    { nb = FNR; split(a[FNR], x, ","); for (i = 1; i <= NF; ++i) {
        if (x[i] ~ /[nN][aA][nN]|[iI][nN][fF]/ || $i ~ /[nN][aA][nN]|[iI][nN][fF]/) { bad = 1; continue }
        d = x[i] - $i; d = d < 0 ? -d : d; m = x[i] < 0 ? -x[i] : x[i]; n = $i < 0 ? -$i : $i
        if (n > m) m = n
        if (m > 0 && d / m > worst) worst = d / m } }
    END { if (bad || na != nb) printf "series_%s_difference=nan\n", name
          else printf "series_%s_difference=%.3e\n", name, worst + 0 }' "$fa" "$fb" | tee -a "$metrics"
}

# MODE+MODE...: one run of CONFIG, checked by each single-run mode in turn
# (the same run read by two checks is not run twice).
if [[ "$mode" == *+* ]]; then
  run "$out/run" "$@"
  for m in ${mode//+/ }; do check "$m" "$out/run" | tee -a "$metrics" || exit 1; done
  mode=checked
fi

case "$mode" in
  checked) ;;
  restart_from)
    every=$1; mapfile -t a < <(sets "$2"); mapfile -t b < <(sets "$3")
    run "$out/straight" "${b[@]}"
    run "$out/checkpointed" "${a[@]}" --set run.checkpoint.every="$every"
    first=$(ls -d "$out"/checkpointed/checkpoints/window_* 2>/dev/null | head -n 1)
    [ -n "$first" ] || { echo "FAIL: run A wrote no checkpoint"; exit 1; }
    run "$out/restarted" "${b[@]}" --restart "$first"
    check compare "$out/straight" "$out/restarted" | tee -a "$metrics" || exit 1
    # Event logs: the restarted run's rows are the straight run's rows after
    # the checkpoint's time, all of them.
    t=$(sed -n 's/^time: //p' "$first/checkpoint.yaml")
    [ -n "$t" ] || { echo "FAIL: no time in $first/checkpoint.yaml"; exit 1; }
    for f in events/collisions.csv events/bonds.csv events/impacts.csv; do
      [ -f "$out/straight/$f" ] || continue
      n=$(awk -F, -v t="$t" 'NR > 1 && $1 + 0 > t + 0' "$out/straight/$f" | wc -l)
      m=$([ -f "$out/restarted/$f" ] && awk 'NR > 1' "$out/restarted/$f" | wc -l || echo 0)
      [ "$n" -eq "$m" ] || { echo "FAIL: $f: $m rows after the restart, the straight run has $n after t = $t"; exit 1; }
      [ "$n" -eq 0 ] || cmp -s <(tail -n "$n" "$out/straight/$f") <(tail -n "$n" "$out/restarted/$f") ||
        { echo "FAIL: $f after the restart differs from the straight run's"; exit 1; }
      echo "${f#events/}: $n events after the restart, identical"
    done ;;
  profile|probes|hydrostatic|channel|walls|fluid_walls|walls_pressure_drop|decay|mass|ramp|impact|pour|crush|momentum|drag|buoyancy|settling|dpm_settling|granular_gas|two_way|dispersion|grid_turbulence|injection|jet|pair_into_mesh|inlet_stream|inlet_mass|rotation|contact_angle|layered|colour_mass|permeability|washburn|injection_phase|grain_interface|bridge|cavity|tg_error|stokes_layer|dfg_cylinder|dfg_cylinder_unsteady|solid_channel|uniform_stream|inlet_profile|divergence|ke_decay|ke_grid|ke_grid_levels|ke_channel|ke_backward_step|grid_turbulence_fv|ibm_steady|ibm_couette|ibm_couette_oscillating|ibm_shedding|ibm_oscillating|ibm_particles|ibm_balance|vortex)
    run "$out/run" "$@"
    check "$mode" "$out/run" | tee -a "$metrics" || exit 1 ;;
  compare|layouts)
    mapfile -t a < <(sets "$1"); mapfile -t b < <(sets "$2")
    run "$out/a" "${a[@]}"; run "$out/b" "${b[@]}"
    check compare "$out/a" "$out/b" | tee -a "$metrics" || exit 1
    if [ "$mode" = layouts ]; then  # run a took the packed layout, run b the spaced one
      grep -q "packed population layout" "$out/a/logs/fluid.log" && pa=1 || pa=0
      grep -q "spaced population layout" "$out/b/logs/fluid.log" && sb=1 || sb=0
      printf 'layout_a_packed=%s\nlayout_b_spaced=%s\n' "$pa" "$sb" | tee -a "$metrics"
    fi
    series_difference particles; series_difference walls; series_difference fluid_walls
    # Event logs, when written, must be the same line for line.
    for f in events/collisions.csv events/bonds.csv events/impacts.csv; do
      if [ -f "$out/a/$f" ] || [ -f "$out/b/$f" ]; then
        [ -f "$out/a/$f" ] && [ -f "$out/b/$f" ] || { echo "FAIL: $f written by one run only"; exit 1; }
        lines=$(wc -l <"$out/a/$f")
        cmp -s "$out/a/$f" "$out/b/$f" || { echo "FAIL: $f differs between the two runs"; exit 1; }
        echo "${f#events/}: $((lines - 1)) events, identical"
      fi
    done ;;
  reflection)
    # ARGS: three override lists: A (the box with its open face), B (a longer
    # box, the reference), C (A with another open face). coflow-check
    # outflow_reflection for A and C against B.
    for n in 1 2 3; do
      mapfile -t s < <(sets "${!n}")
      run "$out/run$n" "${s[@]}"
    done
    check outflow_reflection "$out/run1" "$out/run2" | tee -a "$metrics" || exit 1
    check outflow_reflection "$out/run3" "$out/run2" | sed 's/^/other_/' | tee -a "$metrics" || exit 1
    awk -F= '/^reflection=/ { a = $2 } /^other_reflection=/ { b = $2 } END { printf "reflection_ratio=%.4f\n", b / a }' "$metrics" | tee -a "$metrics" || exit 1 ;;
  pair)
    # ARGS: a coflow-check mode that reads two runs, then two override lists
    # (each may start with config=FILE); runs both, then that mode.
    what=$1; shift
    for n in 1 2; do
      mapfile -t s < <(sets "${!n}")
      run "$out/run$n" "${s[@]}"
    done
    check "$what" "$out/run1" "$out/run2" | tee -a "$metrics" || exit 1 ;;
  order|order_tg|order_stokes)
    # order: steady profiles (coflow-check profile); order_tg: the Taylor-Green
    # vortex at the end (coflow-check tg_error); order_stokes: Stokes'
    # oscillating wall (coflow-check stokes_layer).
    what=profile; [ "$mode" = order_tg ] && what=tg_error; [ "$mode" = order_stokes ] && what=stokes_layer
    errs=()
    for n in 1 2 3; do
      mapfile -t s < <(sets "${!n}")
      run "$out/res$n" "${s[@]}"
      e=$(check "$what" "$out/res$n" | sed -n 's/^l2_error=//p') || exit 1
      echo "l2_error_$n=$e" | tee -a "$metrics"; errs+=("$e")
    done
    awk -v a="${errs[0]}" -v b="${errs[1]}" -v c="${errs[2]}" \
      'BEGIN { printf "order_12=%.4f\norder_23=%.4f\n", log(a/b)/log(2), log(b/c)/log(2) }' | tee -a "$metrics" || exit 1 ;;
  order_time)
    for n in 1 2 3 4; do
      mapfile -t s < <(sets "${!n}")
      run "$out/dt$n" "${s[@]}"
    done
    diffs=()
    for n in 1 2 3; do
      e=$(check compare "$out/dt$n" "$out/dt$((n + 1))" | sed -n 's/^max_difference=//p') || exit 1
      echo "difference_$n=$e" | tee -a "$metrics"; diffs+=("$e")
    done
    awk -v a="${diffs[0]}" -v b="${diffs[1]}" -v c="${diffs[2]}" \
      'BEGIN { printf "order_12=%.4f\norder_23=%.4f\n", log(a/b)/log(2), log(b/c)/log(2) }' | tee -a "$metrics" || exit 1 ;;
  laplace)
    # ARGS: override lists, one droplet each (radii); per droplet its
    # Laplace error and colour drift, then the surface tension of the
    # least-squares fit of Laplace's law dp = gamma' / R (2D; 2 gamma' / R in
    # 3D) against the requested one.
    xs=(); ys=(); worst=0; drift=0
    for n in $(seq 1 $#); do
      mapfile -t s < <(sets "${!n}")
      run "$out/drop$n" "${s[@]}"
      m=$(check laplace "$out/drop$n") || exit 1
      echo "$m" | sed "s/^/drop${n}_/" | tee -a "$metrics"
      xs+=("$(echo "$m" | sed -n 's/^radius=//p')"); ys+=("$(echo "$m" | sed -n 's/^pressure_jump=//p')")
      e=$(echo "$m" | sed -n 's/^laplace_error=//p'); c=$(echo "$m" | sed -n 's/^colour_mass_drift=//p')
      worst=$(awk -v a="$worst" -v b="$e" 'BEGIN { print (b > a || b != b) ? b : a }')
      drift=$(awk -v a="$drift" -v b="$c" 'BEGIN { print (b > a || b != b) ? b : a }')
    done
    gamma=$(check laplace "$out/drop1" | sed -n 's/^surface_tension=//p')
    dim=$(check laplace "$out/drop1" | sed -n 's/^dimensions=//p')
    printf '%s\n' "${xs[@]}" | paste -d' ' - <(printf '%s\n' "${ys[@]}") |
      awk -v g="$gamma" -v dim="$dim" -v worst="$worst" -v drift="$drift" '
        { x = 1 / $1; y = $2; n++; sx += x; sy += y; sxx += x * x; sxy += x * y }
        END { slope = sxy / sxx; k = (dim == 3 ? 2 : 1); e = slope / k / g - 1
              printf "surface_tension_fit=%.6e\nsurface_tension_error=%.6e\nlaplace_error_max=%s\ncolour_mass_drift_max=%s\n",
                     slope / k, (e < 0 ? -e : e), worst, drift }' | tee -a "$metrics" || exit 1 ;;
  tau_independence)
    # ARGS: two override lists (two relaxation times); permeability of each
    # and the relative difference of their K.
    ks=()
    for n in 1 2; do
      mapfile -t s < <(sets "${!n}")
      run "$out/run$n" "${s[@]}"
      k=$(check permeability "$out/run$n" | sed -n 's/^K=//p') || exit 1
      echo "K_$n=$k" | tee -a "$metrics"; ks+=("$k")
    done
    awk -v a="${ks[0]}" -v b="${ks[1]}" 'BEGIN { d = a / b - 1; printf "K_difference=%.6e\n", d < 0 ? -d : d }' | tee -a "$metrics" || exit 1 ;;
  formulations)
    run "$out/standard" --set fluid.lbm.formulation=standard "$@"
    run "$out/incompressible" --set fluid.lbm.formulation=incompressible "$@"
    es=$(check profile "$out/standard" | sed -n 's/^l2_error=//p') || exit 1
    ei=$(check profile "$out/incompressible" | sed -n 's/^l2_error=//p') || exit 1
    oe=$(check profile "$out/incompressible" | sed -n 's/^odd_even=//p') || exit 1
    awk -v s="$es" -v i="$ei" -v o="$oe" 'BEGIN { printf "l2_error_standard=%s\nl2_error_incompressible=%s\nerror_ratio=%.4f\nodd_even_incompressible=%s\n", s, i, i/s, o }' | tee -a "$metrics" || exit 1 ;;
  address_limit)
    # ARGS: an address-space limit (KiB) below lbm's spaced reservation: the run
    # under it must fall back to the packed layout, say so, and match a run
    # without the limit bit for bit.
    run "$out/free"
    ( ulimit -v "$1" && run "$out/limited" ) || { echo "FAIL: the run under ulimit -v $1 (or the limit itself) failed"; exit 1; }
    fallback=0; grep -q "packed layout (slower)" "$out/limited.log" && fallback=1
    echo "fallback_logged=$fallback" | tee -a "$metrics" || exit 1
    check compare "$out/limited" "$out/free" | tee -a "$metrics" || exit 1 ;;
  damping)
    # ARGS: local damping values; restitution must fall as damping grows.
    prev=""; mono=1; list=""
    for a in "$@"; do
      run "$out/alpha-$a" --set particles.contact.local_damping="$a"
      e=$(check impact "$out/alpha-$a" | sed -n 's/^restitution=//p') || exit 1
      echo "restitution_alpha_$a=$e" | tee -a "$metrics"; list="$list $a:$e"
      # awk compares a non-number ("nan") as a string: only numbers count.
      [[ "$e" =~ ^[0-9.]+([eE][-+]?[0-9]+)?$ ]] || mono=0
      if [ -n "$prev" ] && ! awk -v p="$prev" -v e="$e" 'BEGIN { exit !(e < p) }'; then mono=0; fi
      prev=$e
    done
    echo "restitution_decreasing=$mono" | tee -a "$metrics" || exit 1 ;;
  openfoam_backward_step)
    # ARGS: NX NY ITERATIONS T1 T2 [--set ...]: CONFIG (the backward-facing
    # step) on NX x NY cells to T1 and to T2 > T1 (coflow-check
    # ke_backward_step of each: how far fv's x_r still moves), and the same
    # case through OpenFOAM's simpleFoam (scripts/openfoam_backward_step.sh,
    # ITERATIONS SIMPLE iterations): the two reattachment lengths at the end,
    # their relative difference, and how far each code's moved. Skipped (77)
    # where OpenFOAM is not installed.
    nx=$1 ny=$2 its=$3 t1=$4 t2=$5; shift 5
    awk -v a="$t1" -v b="$t2" 'BEGIN { r = b > a ? a / (b - a) : 0.5  # T1 / (T2 - T1), a whole number
      exit !(a + 0 == a && b + 0 == b && a > 0 && b > a && (r - int(r + 0.5)) ^ 2 < 1e-18) }' ||
      { echo "FAIL: openfoam_backward_step needs numbers 0 < T1 < T2, T1 a multiple of T2 - T1 (given $t1, $t2)"; exit 1; }
    every=$(awk -v a="$t1" -v b="$t2" 'BEGIN { printf "%.17g", b - a }')
    command -v simpleFoam >/dev/null || { echo "SKIP: simpleFoam not found (Debian package openfoam; scripts/setup installs it)"; exit 77; }
    # The run to T2 goes on from the run to T1's checkpoint at T1 (a restart
    # ends where the straight run ends, bit for bit: restart.fv_k_epsilon_log_law;
    # both write snapshots every T2 - T1, as a restart needs).
    run "$out/early" --set "domain.cells=[$nx,$ny,1]" --set run.end_time="$t1" --set run.output.every="$every" \
      --set run.checkpoint.every="$t1" "$@"
    check ke_backward_step "$out/early" | sed 's/^/early_/' | tee -a "$metrics" || exit 1
    at_t1=$(ls -d "$out"/early/checkpoints/window_*[0-9] 2>/dev/null | tail -n 1)
    [ -n "$at_t1" ] || { echo "FAIL: the run to T1 wrote no checkpoint"; exit 1; }
    run "$out/run" --restart "$at_t1" --set "domain.cells=[$nx,$ny,1]" --set run.end_time="$t2" \
      --set run.output.every="$every" "$@"
    check ke_backward_step "$out/run" | tee -a "$metrics" || exit 1
    rm -rf "$out/openfoam"
    "$here/../../scripts/openfoam_backward_step.sh" "$nx" "$ny" "$its" "$out/openfoam" | sed 's/^/openfoam_/' |
      tee -a "$metrics" || { echo "FAIL: scripts/openfoam_backward_step.sh (its log: $out/openfoam/simpleFoam.log)"; exit 1; }
    awk -F= 'function off(a, b) { d = a / b - 1; return d < 0 ? -d : d }  # |a / b - 1|
      { v[$1] = $2 } END {
      printf "x_r_vs_openfoam=%.4e\nfloor_u_min_vs_openfoam=%.4e\nfloor_k_vs_openfoam=%.4e\n",
        off(v["x_r_over_h"], v["openfoam_x_r_over_h"]), off(v["floor_u_min"], v["openfoam_floor_u_min"]),
        off(v["floor_k_20h"], v["openfoam_floor_k_20h"])
      printf "x_r_settled=%.4e\nopenfoam_x_r_settled=%.4e\n", off(v["early_x_r_over_h"], v["x_r_over_h"]),
        off(v["openfoam_half_x_r_over_h"], v["openfoam_x_r_over_h"]) }' "$metrics" | tee -a "$metrics" || exit 1 ;;
  *) echo "FAIL: unknown mode $mode"; exit 1 ;;
esac

status=0; n=0
while IFS=, read -r c metric op bound source; do
  [ "$c" = "$case_name" ] || continue
  n=$((n + 1))
  value=$(sed -n "s/^$metric=//p" "$metrics" | tail -n 1)
  if [ -z "$value" ]; then echo "FAIL: metric $metric not produced"; status=1; continue; fi
  if awk -v v="$value" -v b="$bound" -v op="$op" 'BEGIN { if (v !~ /^[-+]?[0-9.]+([eE][-+]?[0-9]+)?$/) exit 1; exit !((op == "<" && v < b) || (op == ">" && v > b) || (op == "<=" && v <= b) || (op == ">=" && v >= b)) }'; then
    echo "ok: $metric = $value $op $bound  ($source)"
  else
    echo "FAIL: $metric = $value, required $op $bound  ($source)"; status=1
  fi
done < "$here/references.csv"
[ $n -gt 0 ] || { echo "FAIL: no reference rows for case $case_name"; exit 1; }
[ $status -ne 0 ] || "$here/../clean_passed.sh" "$out"  # a failure keeps its snapshots
exit $status
