// dpm: the point particles of seed 003 (chapters 3-4) with structure-of-arrays
// storage and O(N) collision detection: a cell list sized so that every pair
// that can touch within the step lies in neighbouring cells (the intent of
// Algorithm 1, §4.2.2.8). Events are taken in the same order as dpm-reference,
// so the two agree to round-off. MPI: each rank owns the particles in its block
// of the decomposition (§4.2.2.7); copies of the particles near a block's faces
// reach the neighbours for the collision search (ghosts); the step's collision
// events are gathered on every rank, so that all take the same earliest-first
// decisions as one rank would; particles that crossed a face migrate.
#pragma once

#include <vector>

#include "particles/dem/dem_common.hpp"
#include "particles/dpm/injection.hpp"
#include "particles/dpm/msd.hpp"
#include "particles/dpm/range_warnings.hpp"
#include "particles/dpm/setup.hpp"
#include "particles/particles_interface.hpp"
#include "particles/wall_impulse.hpp"
#include "particles/store/domain.hpp"
#include "particles/store/particle_store.hpp"

namespace coflow::particles::store {
// A fluid sample travels as its 10 doubles: u, vorticity, k, epsilon, rho, mu.
template <>
struct Codec<dpm::FluidSample> {
  static constexpr std::size_t doubles = 10;
  static void put(const dpm::FluidSample& f, double* out) {
    for (int d = 0; d < 3; ++d) {
      out[d] = f.u[d];
      out[3 + d] = f.vorticity[d];
    }
    out[6] = f.k;
    out[7] = f.epsilon;
    out[8] = f.rho;
    out[9] = f.mu;
  }
  static dpm::FluidSample get(const double* in) {
    return {dpm::V3(in), dpm::V3(in + 3), in[6], in[7], in[8], in[9]};
  }
};
}  // namespace coflow::particles::store

namespace coflow::particles {

class DpmSolver final : public ParticleSolver {
 public:
  struct Params {
    void visit(config::Visitor&) {}  // common particle keys only
  };
  DpmSolver(const Setup& setup, const Params& params);

  double time_step() const override { return dt_; }
  void advance(double dt, long substeps) override;
  double time() const override { return time_; }
  long steps() const override { return steps_; }
  const ParticleArrays& particles() const override { return p_; }
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
  void write_statistics(const std::string& series_dir) override;

  void step(double h);
  // Collision candidates by cell lists (default) or by all pairs (for the
  // benchmark's comparison).
  void use_all_pairs(bool on) { all_pairs_ = on; }

 private:
  double stable_step() const;
  void find_pair_events(double h, std::vector<dpm::Event>& out);
  void sort_into_cells(double h);
  [[gnu::always_inline]] inline int neighbour_cells(std::size_t c, long* cursor, long* nb) const;
  void move_freely(double h);
  void collect_events(double h);
  void apply_events();
  void commit_states(double h);
  dpm::V3 after_event(std::size_t i, double h);  // the rest of the step after i's event (dpm::finish_step)
  void set_derived();
  void inject(double h);
  void keep_owned();  // every rank holds all: keep this rank's
  void add_ghosts(double h);
  void share_events();
  void save_msd(const std::string& dir) const;
  void load_msd(const std::string& dir);

  MPI_Comm comm_;
  store::Domain domain_;
  int rank_ = 0, size_ = 1;
  // The particles: the common attributes, then the diameter, density, impulse
  // given to the fluid, fluid sample, turbulent fluctuation seen (dispersion)
  // and whether it has started; store_ moves them together.
  ParticleArrays p_;
  std::vector<double> D_, rho_p_, impulse_;
  std::vector<DepartedImpulse> departed_;  // in the last advance(), until take_departed
  std::vector<dpm::FluidSample> fluid_;
  std::vector<double> uprime_;
  std::vector<char> turbulent_;
  std::vector<double> msd_track_;  // dpm::Msd::kTrack per particle
  store::ParticleStore store_{p_};
  dpm::Msd msd_;
  std::vector<dpm::FluidSample> seen_;
  dpm::DpmSetup s_;
  std::vector<dpm::Inlet> inlets_;
  dpm::ProbeFluid probe_fluid_;  // the fluid at the inlets, this window (rank 0)
  std::int64_t next_id_ = 0;
  std::vector<dpm::Entering> entering_;
  std::vector<std::pair<dpm::V3, double>> nearby_;
  const ParticleParams& params_;
  double dt_ = 0.0;
  double time_ = 0.0;
  long steps_ = 0;
  long collisions_ = 0, wall_collisions_ = 0;
  dpm::RangeWarnings ranges_;  // correlations used beyond their range, warned once
  bool all_pairs_ = false;
  dem::EventRecorder events_;
  WallImpulse wall_impulse_;
  // sparse cell list (rebuilt every step)
  struct Packed {
    dpm::V3 x, u;
    double D;
    std::int64_t id;
    std::size_t index;
  };
  long nc_[3] = {1, 1, 1};  // collision cells per axis
  std::vector<long> start_, keys_, cell_;  // per occupied cell: first packed row; its key; per particle: key
  // Where the grid has at most 32 cells per particle: key -> occupied slot + 1
  // (0: empty), so that a cell's 27 neighbours are 27 reads (else the sorted
  // keys are searched: a jet's column can span millions of empty cells).
  std::vector<int> slot_of_;
  std::vector<std::size_t> order_;
  std::vector<Packed> packed_;
  std::vector<dpm::Motion> moved_;
  std::vector<dpm::V3> u_;
  // owned particles followed by ghosts (for the collision search): start
  // position, trajectory velocity, velocities after the step, diameter, mass, id
  struct Near {
    dpm::V3 x, u, v, w;
    double D, m;
    std::int64_t id;
    int species;
  };
  std::vector<Near> near_;
  std::vector<dpm::Event> ev_;
  std::vector<double> hit_;
  std::vector<char> pair_hit_;
  std::vector<int> tris_;  // mesh candidates (scratch)
};

}  // namespace coflow::particles
