// dem-reference: the soft-sphere DEM written as plainly as possible: one struct
// per particle, every pair tested, contacts in an ordered map. The oracle for dem.
#pragma once

#include <map>
#include <utility>
#include <vector>

#include "particles/dem/dem_common.hpp"
#include "particles/particles_interface.hpp"
#include "particles/wall_impulse.hpp"

namespace coflow::particles {

class DemReference final : public ParticleSolver {
 public:
  using Params = dem::DemParams;
  DemReference(const Setup& setup, const Params& params);

  double time_step() const override { return s_.dt; }
  void advance(double dt, long substeps) override;
  double time() const override { return time_; }
  long steps() const override { return steps_; }
  const ParticleArrays& particles() const override;
  void set_hydrodynamic(std::span<const double> force, std::span<const double> torque) override;
  ParticleStats stats() override;
  void record_events(bool collisions, bool bonds) override { events_.enable(collisions, bonds); }
  ParticleEvents take_events() override { return events_.take(); }
  coupler::ExactSums take_wall_impulse() override { return wall_impulse_.take(); }
  void save(const std::string& dir) override;
  void load(const std::string& dir, long steps, double time) override;

  void step(double h);

 private:
  void pair_forces(double h, std::vector<std::size_t>& crushed);
  void wall_forces(double h);
  void mesh_forces(double h);
  void move(double h, const std::vector<std::size_t>& crushed);
  struct Particle {
    std::int64_t id;
    int species;
    dem::V3 x, v, w;
    double r, m, I;
    dem::V3 F, T, Fh, Th;
  };
  std::vector<Particle> p_;
  std::map<std::pair<std::int64_t, std::int64_t>, dem::ContactState> contacts_;
  std::map<std::pair<std::int64_t, int>, dem::ContactState> walls_;
  dem::DemSetup s_;
  MPI_Comm comm_;
  const ParticleParams& params_;
  double time_ = 0.0;
  long steps_ = 0;
  long collisions_ = 0, wall_collisions_ = 0, broken_ = 0;
  dem::EventRecorder events_;
  WallImpulse wall_impulse_;
  mutable ParticleArrays view_;
};

}  // namespace coflow::particles
