#include "immersed/psm/params.hpp"

namespace coflow::immersed {

void PsmParams::visit(config::Visitor& v) {
  v("refinement", refinement,
    "octree levels for the cells a sphere surface cuts (3: 8^3 sub-cells, raw sphere volume within 3e-4 at "
    "radius 4 cells; 4: within 7e-5); the cut cells are then scaled so that the total is the sphere's volume",
    config::in_range(0, 8));
  v("buoyancy", buoyancy,
    "add the buoyancy -rho_f V g to each particle (the fluid carries no hydrostatic pressure gradient)");
}

}  // namespace coflow::immersed
