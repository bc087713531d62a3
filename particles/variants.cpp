// The particle solvers by name; their schemas are in particles/schema.cpp.
#include "particles/dem/dem_solver.hpp"
#include "particles/dem_reference/dem_reference.hpp"
#include "particles/dpm/dpm_solver.hpp"
#include "particles/dpm_reference/dpm_reference.hpp"
#include "particles/schema.hpp"

namespace coflow::particles {

void register_particles_variants(Registry<ParticleSolver>& r) {
  r.add<DemSolver>("dem");
  r.add<DemReference>("dem-reference");
  r.add<DpmSolver>("dpm");
  r.add<DpmReference>("dpm-reference");
}

Registry<ParticleSolver>& registry() {
  static Registry<ParticleSolver> r = [] {
    Registry<ParticleSolver> reg;
    register_particles_variants(reg);
    return reg;
  }();
  return r;
}

}  // namespace coflow::particles
