// dem: the soft-sphere DEM of seed 000 §2.2 with an O(N) Verlet list (built from
// cell lists, rebuilt when a particle has moved half the skin), structure-of-
// arrays particles, and contact histories kept beside the listed pairs (in a map
// keyed by ids only while the list is rebuilt, for migration and checkpoints).
// Pairs are visited in the same order as dem-reference, so the two agree to
// round-off.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "particles/dem/dem_common.hpp"
#include "particles/particles_interface.hpp"
#include "particles/store/domain.hpp"
#include "particles/store/particle_store.hpp"
#include "particles/wall_impulse.hpp"

namespace coflow::particles {

class DemSolver final : public ParticleSolver {
 public:
  using Params = dem::DemParams;
  DemSolver(const Setup& setup, const Params& params);

  double time_step() const override { return s_.dt; }
  void advance(double dt, long substeps) override;
  double time() const override { return time_; }
  long steps() const override { return steps_; }
  const ParticleArrays& particles() const override { return p_; }
  void set_hydrodynamic(std::span<const double> force, std::span<const double> torque) override;
  ParticleStats stats() override;
  void record_events(bool collisions, bool bonds) override { events_.enable(collisions, bonds); }
  ParticleEvents take_events() override { return events_.take(); }
  coupler::ExactSums take_wall_impulse() override { return wall_impulse_.take(); }
  void save(const std::string& dir) override;
  void load(const std::string& dir, long steps, double time) override;

  void step(double h);

 private:
  long crushed_substeps(double h) const;
  void pair_contact(std::size_t i, std::size_t j, long k, double h);
  void face_contacts(double h);
  void mesh_contacts(double h);
  void crush_grains();
  void integrate_owned(double h);
  void drop_outlets();  // parts of a step h once crushed grains need a shorter one
  void build_cells();
  void window_axis(int d, std::vector<long>& at);
  // Verlet list: for each particle i, the j > i within reach + skin (CSR).
  void build_list();
  std::vector<std::pair<long, long>> far_bonds() const;
  bool list_stale() const;
  // Histories back into contacts_ (keyed by ids) from the list; before the
  // local indices change, the list is synced and dropped.
  void sync_contacts();
  void invalidate_list();
  // MPI: ghosts of neighbours' particles within reach, sorted in by id;
  // drop_ghosts() keeps only the particles marked owned (it also removes those
  // leaving through outlets); particles that left the block move to their new
  // owner with their contact histories.
  void add_ghosts();
  void drop_ghosts();
  void migrate();
  void assign_particles(ParticleArrays a);  // every rank holds all: keep the owned ones
  template <class F>
  void for_candidates(std::size_t i, F&& f);
  static std::uint64_t key(std::int64_t a, std::int64_t b) {
    return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint64_t>(b);
  }

  // The particles: the common attributes, the torque of the step, the
  // hydrodynamic force and torque of the window, and whether this rank owns
  // the particle (0: a ghost copy); store_ moves them together.
  ParticleArrays p_;
  std::vector<double> torque_, fh_, th_;
  std::vector<char> owned_;
  store::ParticleStore store_{p_};
  std::unordered_map<std::uint64_t, dem::ContactState> contacts_, walls_;
  dem::DemSetup s_;
  MPI_Comm comm_;
  const ParticleParams& params_;
  store::Domain domain_;
  int rank_ = 0, size_ = 1;
  // cell list
  double cell_size_ = 0.0;
  double extra_ = 0.0;   // reach beyond contact: bond gap or bond stretch
  double skin_ = 0.0;
  std::vector<long> list_start_, list_items_;
  std::vector<double> list_x_;  // positions at the last build
  std::vector<dem::ContactState> list_state_;  // history of each listed pair
  std::vector<char> list_live_;                // 1: touching or bonded
  bool list_valid_ = false;
  long list_builds_ = 0;
  std::array<long, 3> nc_{1, 1, 1};
  std::vector<long> cell_of_, cell_start_, cell_items_;  // cell_of_: in the window (build_cells)
  std::array<long, 3> win_n_{1, 1, 1};                   // the window's cells per axis
  std::array<bool, 3> win_wrap_{false, false, false};    // the window is the whole periodic axis
  bool sparse_ = false;             // a window mostly empty: cell_items_ sorted by cell, no cell_start_
  std::vector<long> sorted_cells_;  // sparse_: the cells of cell_items_, in order
  std::vector<long> candidates_;
  std::vector<std::size_t> crushed_;
  std::vector<dem::MeshContact> mesh_hits_;
  double time_ = 0.0;
  long steps_ = 0;
  long collisions_ = 0, wall_collisions_ = 0, broken_ = 0;
  dem::EventRecorder events_;
  WallImpulse wall_impulse_;
};

}  // namespace coflow::particles
