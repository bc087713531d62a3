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
# warning, and --strict passes. high_mach.yaml (tau 1.4): Mach 2.078 is a warning; --strict
# makes it exit status 2, and the advice is the tau of Mach 0.1:
# 0.5 + 0.9 x 0.1 / 2.078 = 0.5433.
set -u
coflow=$1 dir=$2 quickstart=$3
fail() { echo "FAIL: $*"; exit 1; }
out=$("$coflow" validate "$dir/dpm_in_water.yaml" --strict) || fail "dpm_in_water --strict: exit status $?"
for want in "tau 0.5199" "dt = 0.00266 s: 1128 steps" "Mach               0.04607" "Re = U L / nu = 40 " \
  "0.25 cells per diameter"; do
  grep -qF -- "$want" <<<"$out" || { echo "$out" | grep '^#'; fail "dpm_in_water: no '$want'"; }
done
grep -q "warning" <<<"$out" && fail "dpm_in_water: unexpected warning"
out=$("$coflow" validate "$quickstart" --strict) || fail "quickstart --strict: exit status $?"
for want in "tau 1.5, incompressible" "dt = 0.0003509 s: 2280 steps to 0.8 s" "65536 cells; at most 32768 per rank" \
  "about 10.45 MiB per rank" "8 cells per diameter"; do
  grep -qF -- "$want" <<<"$out" || { echo "$out" | grep '^#'; fail "quickstart: no '$want'"; }
done
out=$("$coflow" validate "$dir/high_mach.yaml" 2>&1) || fail "high_mach without --strict: exit status $?"
grep -qF "warning: fluid: Mach 2.078 > 0.1" <<<"$out" || fail "high_mach: no Mach warning"
grep -qF "fluid.lbm.tau 0.5433 gives Mach 0.1" <<<"$out" || fail "high_mach: no tau advice"
err=$(mktemp)
"$coflow" validate "$dir/high_mach.yaml" --strict >/dev/null 2>"$err"
rc=$?
[ $rc -eq 2 ] || fail "high_mach --strict: exit status $rc, expected 2"
grep -qF "1 warning(s) and --strict" "$err" || fail "high_mach --strict: no message"
rm -f "$err"
echo "pre-run report: numbers as computed by hand, warning and --strict: ok"
