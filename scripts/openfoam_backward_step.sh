#!/usr/bin/env bash
# The backward-facing step of configs/validation/fv_ke_backward_step.yaml run
# through OpenFOAM's simpleFoam (Debian package openfoam, v1912; scripts/setup
# installs it) with the same model: standard k-epsilon, the k-based wall
# functions (nutkWallFunction, kqRWallFunction, epsilonWallFunction), the
# same box (40 H x 9 H, the step's edge at x = 0), grid, inlet tables
# (configs/validation/bfs_inlet_*.csv, linear between rows at the face
# centres, as fv reads them), pressure outlet and van Leer's limiter (k and
# epsilon per component; U by vanLeerV, limited along the direction of its
# steepest change). It is the peer of fv's wall functions: a second
# implementation of the same model family on the same grid. simpleFoam finds
# the steady state (fv runs in time to it). The box, viscosity and initial k
# and epsilon below are the config's, written again here: change both
# together.
#
#   scripts/openfoam_backward_step.sh [NX NY [ITERATIONS [DIR]]]
#   (default 320 144, 4000 SIMPLE iterations (an even number), a temporary directory)
#
# Two environment variables run other models of the same case (docs/validation.md,
# not tests; neither is fv's):
#   MODEL=LaunderSharmaKE (low-Reynolds-number k-epsilon) or kOmegaSST: resolved
#     walls instead of wall functions (k on the walls 1e-12, near zero; epsilon 1e-12, or
#     OpenFOAM's omegaWallFunction; nutLowReWallFunction), default kEpsilon;
#   GRADE=R: cells graded along y towards both walls, the largest R times the
#     first (blockMesh's expansion ratio of each half; NY even), default 1
#     (uniform). GRADE=200 with NY = 240 puts the first cells 1e-3 H high
#     (y+ about 0.7 at the inlet's upper wall).
#
# Prints, as coflow-check ke_backward_step does, x_r_over_h: where the x
# velocity of the floor's first cells turns from upstream to downstream for
# the last time (linear between cell centres), floor_u_min, and floor_k_20h
# (k of the floor's first cells at x = 20 H); and the same after half the
# iterations (half_x_r_over_h: how far from steady).
set -euo pipefail
nx=${1:-320}
ny=${2:-144}
here=$(cd "$(dirname "$0")/.." && pwd)
iterations=${3:-4000}
model=${MODEL:-kEpsilon} grade=${GRADE:-1}
case $model in kEpsilon | LaunderSharmaKE | kOmegaSST) ;; *) echo "MODEL must be kEpsilon, LaunderSharmaKE or kOmegaSST" >&2; exit 1 ;; esac
[[ $grade =~ ^[0-9]+([.][0-9]*)?([eE][-+]?[0-9]+)?$ ]] || { echo "GRADE must be a number (given $grade)" >&2; exit 1; }
# blockMesh's grading along y: 1, or each half towards its wall.
y_grading=$(awk -v g="$grade" -v ny="$ny" 'BEGIN {
  if (!(g >= 1 && (g == 1 || (ny % 2 == 0 && ny >= 4)))) exit 1
  if (g == 1) print 1; else printf "((0.5 0.5 %s) (0.5 0.5 %.12g))\n", g, 1 / g }') ||
  { echo "GRADE must be at least 1 (and NY even and at least 4 when it is not 1)" >&2; exit 1; }
[ $((iterations % 2)) -eq 0 ] && [ "$iterations" -ge 2 ] || { echo "ITERATIONS must be even (it writes after half of them)" >&2; exit 1; }
dir=${4:-$(mktemp -d /tmp/coflow-openfoam-bfs.XXXXXX)}
command -v simpleFoam >/dev/null || { echo "simpleFoam not found (Debian package openfoam; scripts/setup installs it)" >&2; exit 1; }
export WM_PROJECT_DIR=${WM_PROJECT_DIR:-/usr/share/openfoam} FOAM_ETC=${FOAM_ETC:-/usr/share/openfoam/etc} OMP_NUM_THREADS=1
mkdir -p "$dir/system" "$dir/constant" "$dir/0"
cd "$dir"
foam_header() { echo "FoamFile { version 2.0; format ascii; class $1; object $2; }"; }

# The inlet's values at the ny face centres (y = (j + 1/2) 9 / ny, or the
# graded cells' centres: each half of ny / 2 cells growing by the factor r
# from the wall, the last GRADE times the first): the tables' rows, linear
# between them (awk reads the tables; `#` lines and the header skipped).
inlet_list() {  # $1: table, $2: column (2, 3), $3: vector or scalar
  awk -F, -v ny="$ny" -v col="$2" -v kind="$3" -v grade="$grade" '
    /^#/ || $1 !~ /^[-+0-9.]/ { next }  # comments and the header
    { n++; y[n] = $1 + 0; v[n] = $col + 0 }
    END {
      for (j = 0; j < ny; j++) yc[j] = (j + 0.5) * 9.0 / ny
      if (grade != 1) {
        half = ny / 2; r = grade ^ (1 / (half - 1)); a = 4.5 * (r - 1) / (r ^ half - 1); y0 = 0
        for (j = 0; j < half; j++) { c = a * r ^ j; yc[j] = y0 + c / 2; yc[ny - 1 - j] = 9 - yc[j]; y0 += c }
      }
      printf "nonuniform List<%s> %d (\n", kind, ny
      for (j = 0; j < ny; j++) {
        p = yc[j]; r = v[n]
        if (p <= y[1]) r = v[1]
        else for (i = 1; i < n; i++) if (p <= y[i + 1]) { w = (p - y[i]) / (y[i + 1] - y[i]); r = (1 - w) * v[i] + w * v[i + 1]; break }
        if (kind == "vector") printf "(%.12g 0 0)\n", r; else printf "%.12g\n", r
      }
      print ")"
    }' "$1"
}
tables=$here/configs/validation
inlet_u=$(inlet_list "$tables/bfs_inlet_velocity.csv" 2 vector)
inlet_k=$(inlet_list "$tables/bfs_inlet_turbulence.csv" 2 scalar)
inlet_eps=$(inlet_list "$tables/bfs_inlet_turbulence.csv" 3 scalar)

cat > system/blockMeshDict <<EOF
$(foam_header dictionary blockMeshDict)
convertToMeters 1;
vertices ((0 0 0) (40 0 0) (40 9 0) (0 9 0) (0 0 0.125) (40 0 0.125) (40 9 0.125) (0 9 0.125));
blocks (hex (0 1 2 3 4 5 6 7) ($nx $ny 1) simpleGrading (1 $y_grading 1));
boundary (
  inlet { type patch; faces ((0 4 7 3)); }
  outlet { type patch; faces ((1 2 6 5)); }
  lowerWall { type wall; faces ((0 1 5 4)); }
  upperWall { type wall; faces ((3 7 6 2)); }
  frontAndBack { type empty; faces ((0 3 2 1) (4 5 6 7)); }
);
EOF
walls() {  # $1: the walls' boundary condition, $2: its value (default the internal field's)
  local v=${2:-\$internalField}
  echo "lowerWall { type $1; value $v; } upperWall { type $1; value $v; } frontAndBack { type empty; }"
}
cat > 0/U <<EOF
$(foam_header volVectorField U)
dimensions [0 1 -1 0 0 0 0]; internalField uniform (1 0 0);
boundaryField { inlet { type fixedValue; value $inlet_u; }
  outlet { type inletOutlet; inletValue uniform (0 0 0); value \$internalField; }
  lowerWall { type noSlip; } upperWall { type noSlip; } frontAndBack { type empty; } }
EOF
cat > 0/p <<EOF
$(foam_header volScalarField p)
dimensions [0 2 -2 0 0 0 0]; internalField uniform 0;
boundaryField { inlet { type zeroGradient; } outlet { type fixedValue; value uniform 0; }
  lowerWall { type zeroGradient; } upperWall { type zeroGradient; } frontAndBack { type empty; } }
EOF
turbulence_field() {  # $1: k, epsilon or omega, $2: its dimensions, $3: its initial value, $4: the inlet's list, $5: the walls' condition, $6: its value there
  cat > "0/$1" <<EOF
$(foam_header volScalarField "$1")
dimensions $2; internalField uniform $3;
boundaryField { inlet { type fixedValue; value $4; }
  outlet { type inletOutlet; inletValue uniform $3; value \$internalField; } $(walls "$5" "${6:-}") }
EOF
}
nut_walls=$(walls nutkWallFunction)
if [ "$model" = kEpsilon ]; then
  turbulence_field k "[0 2 -2 0 0 0 0]" 1.5e-4 "$inlet_k" kqRWallFunction
  turbulence_field epsilon "[0 2 -3 0 0 0 0]" 2.2e-6 "$inlet_eps" epsilonWallFunction
else  # resolved walls
  nut_walls=$(walls nutLowReWallFunction "uniform 0")
  turbulence_field k "[0 2 -2 0 0 0 0]" 1.5e-4 "$inlet_k" fixedValue "uniform 1e-12"
  if [ "$model" = kOmegaSST ]; then  # omega = epsilon / (C_mu k) at the inlet
    inlet_omega=$(paste -d'|' <(echo "$inlet_eps") <(echo "$inlet_k") |
      awk -F'|' 'NR == 1 { print $1; next } /^\)/ { print ")"; next } { printf "%.12g\n", $1 / (0.09 * $2) }')
    turbulence_field omega "[0 0 -1 0 0 0 0]" 0.163 "$inlet_omega" omegaWallFunction
  else
    turbulence_field epsilon "[0 2 -3 0 0 0 0]" 2.2e-6 "$inlet_eps" fixedValue "uniform 1e-12"
  fi
fi
cat > 0/nut <<EOF
$(foam_header volScalarField nut)
dimensions [0 2 -1 0 0 0 0]; internalField uniform 0;
boundaryField { inlet { type calculated; value uniform 0; } outlet { type calculated; value uniform 0; }
  $nut_walls }
EOF
cat > constant/transportProperties <<EOF
$(foam_header dictionary transportProperties)
transportModel Newtonian; nu 2.7777778e-5;
EOF
cat > constant/turbulenceProperties <<EOF
$(foam_header dictionary turbulenceProperties)
simulationType RAS; RAS { RASModel $model; turbulence on; printCoeffs on; }
EOF
cat > system/controlDict <<EOF
$(foam_header dictionary controlDict)
application simpleFoam; startFrom startTime; startTime 0; stopAt endTime; endTime $iterations; deltaT 1;
writeControl timeStep; writeInterval $((iterations / 2)); purgeWrite 0; writeFormat ascii; writePrecision 12;
runTimeModifiable false;
EOF
cat > system/fvSchemes <<EOF
$(foam_header dictionary fvSchemes)
ddtSchemes { default steadyState; } gradSchemes { default Gauss linear; }
divSchemes { default none; div(phi,U) bounded Gauss vanLeerV; div(phi,k) bounded Gauss vanLeer;
  div(phi,epsilon) bounded Gauss vanLeer; div(phi,omega) bounded Gauss vanLeer;
  div((nuEff*dev2(T(grad(U))))) Gauss linear; }
laplacianSchemes { default Gauss linear corrected; } interpolationSchemes { default linear; }
snGradSchemes { default corrected; } wallDist { method meshWave; }
EOF
cat > system/fvSolution <<EOF
$(foam_header dictionary fvSolution)
solvers { p { solver GAMG; smoother GaussSeidel; tolerance 1e-9; relTol 0.05; }
  "(U|k|epsilon|omega)" { solver smoothSolver; smoother symGaussSeidel; tolerance 1e-10; relTol 0.1; } }
SIMPLE { nNonOrthogonalCorrectors 0; consistent yes; }
relaxationFactors { equations { U 0.9; "(k|epsilon|omega)" 0.7; } fields { p 1; } }
EOF
blockMesh > blockMesh.log 2>&1
simpleFoam > simpleFoam.log 2>&1 || { tail -20 simpleFoam.log >&2; exit 1; }
echo "case=$dir"
echo "iterations=$(grep -c '^Time = ' simpleFoam.log)"
# The floor's first cells: the first nx cells of U and k (x fastest, then y).
first_row() {  # $1: a field file; the x component (or value) of its first nx cells
  [ -f "$1" ] || { echo "$1: not written" >&2; return 1; }
  awk -v nx="$nx" '
    /^internalField/ && !/nonuniform/ { bad = 1; exit }  # a uniform field: no cells listed
    /^internalField/ { on = 1; next }
    on == 1 && /^\(/ { on = 2; next }
    on == 2 && i < nx { gsub(/[()]/, ""); print $1; i++ }
    END { if (bad || i < nx) { print "'"$1"': fewer than " nx " cells in internalField" > "/dev/stderr"; exit 1 } }' "$1"
}
reattachment() {  # $1: a time directory, $2: a prefix for the names printed
  local u k
  u=$(first_row "$1/U") && k=$(first_row "$1/k") || exit 1
  paste <(echo "$u") <(echo "$k") | awk -v nx="$nx" -v pre="$2" '
    { u[NR - 1] = $1 + 0; k[NR - 1] = $2 + 0 }
    END {
      if (NR != nx) exit 1
      dx = 40.0 / nx; xr = "nan"; umin = 0
      for (i = 0; i + 1 < nx; i++) {
        if (u[i] < umin) umin = u[i]
        if (u[i] < 0 && u[i + 1] >= 0) xr = sprintf("%.4f", (i + 0.5 + u[i] / (u[i] - u[i + 1])) * dx)
      }
      at = 20.0 / dx - 0.5; i = int(at); w = at - i  # x = 20 H, linear between cell centres
      printf "%sfloor_u_min=%.4f\n%sx_r_over_h=%s\n%sfloor_k_20h=%.6e\n", pre, umin, pre, xr, pre, (1 - w) * k[i] + w * k[i + 1]
    }'
}
reattachment "$((iterations / 2))" half_
reattachment "$iterations" ""
