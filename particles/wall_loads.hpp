// series/walls.csv: the mean force the particles exert on each wall over each
// series interval, in N: the domain faces that are walls for the particles
// (not periodic, not outlets), then the mesh walls of particles.walls
// (mesh0, mesh1, ... in their order). Columns time, <wall>_fx, _fy, _fz. The
// impulses are summed over the ranks every window, so the sums are the same
// on every rank and a restart (the checkpoint keeps them) continues them bit
// for bit.
#pragma once

#include <string>
#include <vector>

#include "coflow/output.hpp"
#include "coflow/session.hpp"
#include "particles/particles_interface.hpp"

namespace coflow::particles {

class WallLoads {
 public:
  // w0: the window restarted from (0: none; else the sums come from the checkpoint).
  WallLoads(coupler::Session& s, const ParticleParams& params, long w0);
  bool empty() const { return names_.empty(); }
  // Every window (collective): add the window's impulses of every rank.
  void add(ParticleSolver& solver);
  // A series row at time t: the mean forces since the previous row.
  void row(double t);
  // Into a checkpoint's particles part (component rank 0).
  void save(const std::string& dir) const;

 private:
  coupler::Session& s_;
  std::vector<std::string> names_;
  std::vector<std::size_t> slots_;  // WallImpulse slot of each named wall
  std::vector<double> sum_;         // impulse since the last row, all slots
  double since_ = 0.0;              // time of the last row
  output::Series series_;
};

}  // namespace coflow::particles
