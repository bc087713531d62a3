#include "immersed/psm/params.hpp"

namespace coflow::immersed {

void PsmParams::visit(config::Visitor& v) {
  v("refinement", refinement,
    "octree levels for the cells a sphere surface cuts (3: 8^3 sub-cells, raw sphere volume within 3e-4 at "
    "radius 4 cells; 4: within 7e-5); the cut cells are then scaled so that the total is the sphere's volume",
    config::in_range(0, 8));
  v("centre_lattice", centre_lattice,
    "the fractions depend only on a sphere's radius and its centre's offset in its cell: they are "
    "computed once for centres on a lattice of h/N per axis, kept, and interpolated trilinearly to the "
    "actual centre (8: a moving sphere costs a few operations per cell, and the interpolation smooths "
    "the octree's leaf noise: largest cell error against 7 levels 0.020, exact centre 0.030, at radius 4 "
    "cells); 0: the octree at the exact centre every window. With N a power of two the lattice's offsets "
    "fall into mirror and permutation classes (35 at N = 8) and only one stencil per class goes through "
    "the octree, with the same numbers. Only species of one diameter keep stencils; particles from a "
    "size distribution or crushing take the exact centre",
    config::in_range(0, 64));
  v("blend_steps", blend_steps,
    "with centre_lattice N > 0, the interpolation's weights between the kept centres are rounded to "
    "multiples of 1/M: the interpolation is taken at a centre moved by at most h / (2 N M) per axis (128: "
    "h/2048 at N = 8; a cell's fraction moves by at most 3 / (2 N M) = 1.5e-3, 7e-4 measured, well below "
    "the octree's own error), and a sphere whose rounded placement has not changed since the last window, "
    "as for most grains of a packed bed, keeps its cells instead of blending them again; 0: not rounded (a "
    "sphere keeps its cells only while its centre is exactly where it was)",
    config::in_range(0, 1 << 20));
  v("buoyancy", buoyancy,
    "add the buoyancy -rho_f V g to each particle (the fluid carries no hydrostatic pressure gradient; the "
    "solid share of fluid.body_force in each cell reaches the particles with the fluid's force, so a body "
    "force that is the fluid's own weight, rho_f g, does not count the buoyancy twice)");
}

}  // namespace coflow::immersed
