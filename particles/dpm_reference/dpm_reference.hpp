// dpm-reference: the point particles of seed 003 (chapters 3-4) written as
// plainly as possible: one struct per particle, serial, every pair tested for
// a collision. The oracle for dpm.
#pragma once

#include <vector>

#include "particles/dem/dem_common.hpp"
#include "particles/dpm/injection.hpp"
#include "particles/dpm/range_warnings.hpp"
#include "particles/dpm/setup.hpp"
#include "particles/particles_interface.hpp"
#include "particles/wall_impulse.hpp"

namespace coflow::particles {

class DpmReference final : public ParticleSolver {
 public:
  struct Params {
    void visit(config::Visitor&) {}  // common particle keys only
  };
  DpmReference(const Setup& setup, const Params& params);

  double time_step() const override { return dt_; }
  void advance(double dt, long substeps) override;
  double time() const override { return time_; }
  long steps() const override { return steps_; }
  const ParticleArrays& particles() const override;
  void set_hydrodynamic(std::span<const double> force, std::span<const double> torque) override;
  void set_fluid(std::span<const double> samples) override;
  std::vector<std::array<double, 3>> probe_points() const override;
  void take_impulse(std::vector<double>& impulse) override;
  void take_departed(std::vector<DepartedImpulse>& departed) override;
  ParticleStats stats() override;
  void record_events(bool collisions, bool bonds) override { events_.enable(collisions, bonds); }
  ParticleEvents take_events() override { return events_.take(); }
  coupler::ExactSums take_wall_impulse() override { return wall_impulse_.take(); }
  void save(const std::string& dir) override;
  void load(const std::string& dir, long steps, double time) override;

  void step(double h);

 private:
  std::vector<dpm::Event> find_events(double h, const std::vector<dpm::V3>& u) const;
  std::vector<double> collide(const std::vector<dpm::Event>& events, const std::vector<dpm::V3>& u,
                              std::vector<dpm::Motion>& next);
  void inject_at_inlets(double h);
  struct Particle {
    std::int64_t id;
    int species;
    dpm::V3 x, v, w;
    double D, m, I, rho_p;
    dpm::FluidSample fluid;  // the fluid at the particle, held over a window
    dpm::V3 last_force;      // fluid force at the end of the last step, for output
    dpm::V3 impulse;         // of the fluid forces since take_impulse()
    dpm::V3 uprime = dpm::V3::Zero();  // turbulent fluctuation seen (dispersion)
    bool turbulent = false;
  };
  double stable_step() const;  // eq. 4.15 over all particles
  std::vector<Particle> p_;
  dpm::DpmSetup s_;
  std::vector<dpm::Inlet> inlets_;
  dpm::ProbeFluid probe_fluid_;  // the fluid at the inlets, this window
  std::int64_t next_id_ = 0;
  const ParticleParams& params_;
  double dt_ = 0.0;
  double time_ = 0.0;
  long steps_ = 0;
  long collisions_ = 0, wall_collisions_ = 0;
  dpm::RangeWarnings ranges_;  // correlations used beyond their range, warned once
  dem::EventRecorder events_;
  WallImpulse wall_impulse_;
  std::vector<DepartedImpulse> departed_;  // in the last advance(), until take_departed
  mutable ParticleArrays view_;
};

}  // namespace coflow::particles
