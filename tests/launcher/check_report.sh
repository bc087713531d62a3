#!/usr/bin/env bash
# check_report.sh COFLOW DIR QUICKSTART: the pre-run report of `coflow validate`.
# QUICKSTART (configs/quickstart.yaml): dx = 0.032 m / 32 = 1 mm, nu = 9.5e-4
# m^2/s, tau = 1.5, so dt = (tau - 1/2) dx^2 / (3 nu) = 1e-6 / 2.85e-3 =
# 3.509e-4 s; run.output.every = 0.1 s is 285 such steps (a whole number: the
# step is kept) and 0.8 s is 2280; 32 x 32 x 64 = 65536 cells, 32768 on each of
# 2 ranks; two copies of 19 doubles per cell, +10 %: 2 x 19 x 8 x 32768 x 1.1 /
# 2^20 = 10.45 MiB; beads of 8 mm on 1 mm cells: 8 cells per diameter.
# dpm_in_water.yaml: dx = 0.002 m, nu = 1e-5 m^2/s, tau = 0.52, U = 0.02 m/s, so
# dt = (tau - 1/2) dx^2 / (3 nu) = 2.667e-3 s; run.output.every = 0.5 s is
# 187.5 such steps, so the step is shortened to 0.5 / 188 = 2.660e-3 s (tau
# 0.5 + 0.02 x 187.5 / 188 = 0.5199): 3 s / that = 1128 steps, U dt/dx = 0.0266,
# Mach = sqrt(3) x that = 0.04607, Re = U L / nu = 0.02 x 0.02 / 1e-5 = 40; no
# warning, and --strict passes. high_mach.yaml (tau 0.58, shortened to
# 0.5 + 0.08 x 46.875 / 47 = 0.57979 so that 47 steps make 0.5 s): Mach
# sqrt(3) x 0.02 x 0.010638 / 0.002 = 0.1843 is a warning (lbm stops above 0.3,
# which validate refuses at a velocity face since 2026-12-07: the case had tau
# 1.4 and Mach 2.078 before); --strict makes it exit status 2, and the advice
# is the tau of Mach 0.1: 0.5 + 0.07979 x 0.1 / 0.1843 = 0.5433.
# Its particles: tau_p = rho_p D^2 / (18 rho nu) = 2500 x 2.5e-7 / 0.18 =
# 3.472e-3 s, so auto takes at most 0.2 x that = 6.944e-4 s (once the inlet
# brings grains: none at the start), at least
# 3 / 6.944e-4 = 4320 steps; the inlet brings 2e-5 kg/s x 3 s / (2500 x pi x
# (5e-4)^3 / 6 kg) = 366.7 grains; wall 4320 x (2e-6 + 183.3 / 3e6) s = 0.27 s.
# The quickstart's beads: m = 7800 x pi x 0.008^3 / 6 = 2.091e-3 kg; auto is
# the smaller of 0.1 x 2 sqrt(m / 2000) = 2.045e-4 s and half of
# 2 sqrt(m / (12 x 7 x 2000)) = 1.116e-4 s: 1.116e-4 s, 0.8 s / that = 7171.
# fv_cavity_3d.yaml (fv): 32 x 32 x 16 cells of 1/32 m, lid 2 m/s, C = 0.5:
# dt = C / (U x 3 x 32) = 2.604e-3 s, 384 steps to 1 s; 16384 cells x 1800
# bytes = 28.12 MiB; 384 x 16384 / 1.8e6 = 3.5 s (fluid/report.cpp's rates).
set -u
coflow=$1 dir=$2 quickstart=$3
fail() { echo "FAIL: $*"; exit 1; }
out=$("$coflow" validate "$dir/dpm_in_water.yaml" --strict) || fail "dpm_in_water --strict: exit status $?"
for want in "tau 0.5199" "dt = 0.00266 s: 1128 steps" "Mach               0.04607" "Re = U L / nu = 40 " \
  "0.25 cells per diameter" "at most 0.0006944 s once grains arrive" "at least 4320 steps to 3 s" \
  "about 367 particles by 3 s" "wall time          about 0.27 s"; do
  grep -qF -- "$want" <<<"$out" || { echo "$out" | grep '^#'; fail "dpm_in_water: no '$want'"; }
done
grep -q "warning" <<<"$out" && fail "dpm_in_water: unexpected warning"
out=$("$coflow" validate "$quickstart" --strict) || fail "quickstart --strict: exit status $?"
for want in "tau 1.5, incompressible" "dt = 0.0003509 s: 2280 steps to 0.8 s" "65536 cells; at most 32768 per rank" \
  "about 10.45 MiB per rank" "8 cells per diameter" "auto: at most 0.0001116 s at the start" "at least 7171 steps"; do
  grep -qF -- "$want" <<<"$out" || { echo "$out" | grep '^#'; fail "quickstart: no '$want'"; }
done
out=$("$coflow" validate "$dir/fv_cavity_3d.yaml" --strict) || fail "fv_cavity_3d --strict: exit status $?"
for want in "16384 cells; at most 16384 per rank" "about 0.002604 s at U" "about 384 steps to 1 s" \
  "about 28.12 MiB per rank" "wall time       about 3.5 s" "Re = U L / nu = 100 "; do
  grep -qF -- "$want" <<<"$out" || { echo "$out" | grep '^#'; fail "fv_cavity_3d: no '$want'"; }
done
out=$("$coflow" validate "$dir/high_mach.yaml" 2>&1) || fail "high_mach without --strict: exit status $?"
grep -qF "warning: fluid: Mach 0.1843 > 0.1" <<<"$out" || fail "high_mach: no Mach warning"
grep -qF "fluid.lbm.tau 0.5433 gives Mach 0.1" <<<"$out" || fail "high_mach: no tau advice"
err=$(mktemp)
"$coflow" validate "$dir/high_mach.yaml" --strict >/dev/null 2>"$err"
rc=$?
[ $rc -eq 2 ] || fail "high_mach --strict: exit status $rc, expected 2"
grep -qF "1 warning(s) and --strict" "$err" || fail "high_mach --strict: no message"
rm -f "$err"
echo "pre-run report: numbers as computed by hand (lbm, fv, dem, dpm), warning and --strict: ok"
