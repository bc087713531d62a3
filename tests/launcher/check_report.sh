#!/usr/bin/env bash
# check_report.sh COFLOW DIR: the pre-run report of `coflow validate`.
# dpm_in_water.yaml: dx = 0.002 m, nu = 1e-5 m^2/s, tau = 0.52, U = 0.02 m/s, so
# dt = (tau - 1/2) dx^2 / (3 nu) = 2.667e-3 s; run.output.every = 0.5 s is
# 187.5 such steps, so the step is shortened to 0.5 / 188 = 2.660e-3 s (tau
# 0.5 + 0.02 x 187.5 / 188 = 0.5199): 3 s / that = 1128 steps, U dt/dx = 0.0266,
# Mach = sqrt(3) x that = 0.04607, Re = U L / nu = 0.02 x 0.02 / 1e-5 = 40; no
# warning, and --strict passes. high_mach.yaml (tau 1.4): Mach 2.078 is a warning; --strict
# makes it exit status 2, and the advice is the tau of Mach 0.1:
# 0.5 + 0.9 x 0.1 / 2.078 = 0.5433.
set -u
coflow=$1 dir=$2
fail() { echo "FAIL: $*"; exit 1; }
out=$("$coflow" validate "$dir/dpm_in_water.yaml" --strict) || fail "dpm_in_water --strict: exit status $?"
for want in "tau 0.5199" "dt = 0.00266 s: 1128 steps" "Mach               0.04607" "Re = U L / nu = 40 " \
  "0.25 cells per diameter"; do
  grep -qF -- "$want" <<<"$out" || { echo "$out" | grep '^#'; fail "dpm_in_water: no '$want'"; }
done
grep -q "warning" <<<"$out" && fail "dpm_in_water: unexpected warning"
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
