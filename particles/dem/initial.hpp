// Initial particles and the DEM configuration shared by dem and dem-reference.
#pragma once

#include <array>
#include <string>

#include "particles/dem/bond_file.hpp"
#include "particles/dem/contact.hpp"
#include "particles/dem/mesh.hpp"
#include "particles/particles_interface.hpp"

namespace coflow::particles::dem {

enum class Face { periodic, wall, outlet };

struct DemSetup {
  ContactLaw law;
  double alpha = 0.0;          // local damping
  double crush = 0.0;          // crush fraction
  double bond_gap = -1.0;      // bond pairs closer than this at start (< 0: no bonds)
  std::string bond_file;       // when set, only the pairs listed there are bonded
  std::array<Face, 6> faces{};
  std::array<double, 6> wall_friction{};
  V3 gravity = V3::Zero();
  V3 lower = V3::Zero(), upper = V3::Zero();
  std::array<bool, 3> periodic{false, false, false};
  double dt = 0.0;             // the step
  bool auto_step = true;       // particles.time_step: auto (the step follows crushed grains' masses)
  double t_frac = 0.1;         // eq. 2.20
  double max_radius = 0.0;
  std::vector<char> fixed;     // per species: held in place
  std::vector<MeshWall> meshes;  // triangle-mesh walls
};

// Key of a wall contact: the faces are 0-5; triangle t of mesh m is 6 + (m << 24) + t.
inline std::int64_t mesh_wall_key(std::size_t mesh, int triangle) {
  return 6 + (static_cast<std::int64_t>(mesh) << 24) + triangle;
}

// The particles of `initial`, with masses and inertias; deterministic from run.seed.
ParticleArrays make_initial(const ParticleParams& p, const config::Config& cfg);

// Faces, law, gravity and the time step (auto: t_frac x min 2 sqrt(m/k), eqs 2.19-2.20).
DemSetup make_setup(const ParticleParams& p, const config::Config& cfg, const ParticleArrays& parts);

}  // namespace coflow::particles::dem
