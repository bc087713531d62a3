// lbm-reference: the lattice Boltzmann method written as plainly as possible,
// serial, distributions stored per cell. It is the test oracle for `lbm`.
#pragma once

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <vector>

#include "fluid/fluid_solver.hpp"
#include "fluid/lbm/params.hpp"
#include "fluid/lbm/setup.hpp"
#include "immersed/ibm/direct_forcing.hpp"

namespace coflow::fluid {

class LbmReference final : public FluidSolver {
 public:
  using Params = lbm::LbmParams;
  LbmReference(const Setup& setup, const Params& params);

  double time_step() const override { return s_.units.dt; }
  void advance(double dt) override;
  double time() const override { return steps_ * s_.units.dt; }
  long steps() const override { return steps_; }
  const coupler::Box& owned() const override { return box_; }
  std::vector<output::GridField> fields(const config::StringList& names) override;
  Diagnostics diagnostics() override;
  std::vector<output::Series::Column> series_columns() const override;
  void save(const std::string& dir) override;
  void load(const std::string& dir, long steps, double time) override;
  void set_solid(std::span<const long> cells, std::span<const double> fraction, std::span<const double> velocity,
                 std::span<const double> wetting) override;
  void take_solid_force(std::vector<double>& force) override;
  void set_source(std::span<const double> force_density) override;
  // Immersed boundaries (immersed_boundary_reference.cpp).
  void set_markers(ibm::MarkerSet markers) override;
  std::vector<double> take_body_loads() override;

  void step();
  // Lattice moments of a cell (rho, u) from the stored post-collision state.
  void moments(long cell, double& rho, double u[3]) const;

 private:
  long index(long i, long j, long k) const { return (k * n_[1] + j) * n_[0] + i; }
  double equilibrium(int q, double rho, const double u[3]) const;
  // The body force plus the cell's momentum source, lattice units.
  void force_at(long c, double F[3]) const;
  // The same with the immersed boundaries' force: what the collision and the
  // fields see.
  void total_force(long c, double F[3]) const;
  // The direct forcing between streaming and collision, on the pulled
  // populations pop(cell, q); sets ibm_force_.
  void force_immersed(const std::function<double(long, int)>& pop);
  // Track the largest u^2 of the step's collisions (the forcing's velocity scale).
  void note_speed(const double* f, const double F[3]);
  // Density and velocity (with half the force, Guo) of one cell's populations.
  void fluid_velocity(const double* f, const double* F, double& rho, double u[3]) const;
  void collide(double* f, const double* F, double tau) const;
  // Two fluids or interior solids (two_phase_reference.cpp).
  bool colours() const { return s_.tp.on || s_.tp.any_solid(); }
  void init_colours();
  void step_colours();
  void close_colours(long i, long j, long k, std::vector<bool>& unknown, const std::vector<double>& post_r,
                     const std::vector<double>& post_b);
  bool close_corner_colours(const long x[3], double* r, double* b, std::vector<double>& f, double psi_known,
                            const std::vector<double>& post_r, const std::vector<double>& post_b);
  // A cell index beyond the box: wrapped across periodic faces, clamped onto
  // the face cell across open ones; whether it lies beyond a wall (which wins)
  // and the last open face crossed.
  struct Beyond {
    bool wall = false;
    const lbm::Face* open = nullptr;
  };
  Beyond beyond(long x[3]) const;
  void bounce_interpolated(long i, long j, long k, int q, int id, const std::vector<double>& post_r,
                           const std::vector<double>& post_b);
  double phi_at(long i, long j, long k) const;  // colour field, solids' colour, wrapped
  bool solid_at(long i, long j, long k) const;
  void colour_gradient(long i, long j, long k, double g[3]) const;
  bool grain_gradient(long i, long j, long k, double g[3]) const;
  double eps_at(long i, long j, long k) const;
  void turn(double g[3], double ns[3], double cos_theta) const;
  void collide_colours(long c, const double g[3], const double F[3]);
  double colour_tau(double psi) const;
  void phase_fields(std::vector<double>& phase, std::vector<double>& solid) const;
  struct Solid {
    double fraction = 0.0;
    double us[3] = {0, 0, 0};    // lattice units
    double wetting = 0.0;        // cos(theta) of the grains (two fluids)
    double gain[3] = {0, 0, 0};  // fluid momentum gained, lattice units, summed over steps
  };
  // Noble & Torczynski partially saturated cell (seed 000 eqs 2.66-2.68).
  void collide_psm(double* f, const double* F, Solid& s) const;
  void collide_grain(long c, const std::vector<double>& r0, const std::vector<double>& b0, const double F[3],
                     Solid& s);
  bool on_open_face(long cell) const;
  void apply_face(int face, std::vector<double>& fs, const std::vector<double>& post);
  void close_corners(std::vector<double>& fs, const std::vector<double>& post) const;
  bool open_face_at(const long x[3], int face) const;
  void rebuild_corner(const long x[3], double* f, double tau,
                      const std::function<double(long, int)>& post) const;
  bool corner_unknown(const bool meets[6], int q) const;
  int meeting_faces(const long x[3]) const;
  void face_state(const double* f, int axis, int s, const lbm::Face& F, const long at[3], const double Fc[3],
                  double& rho, double u[3]) const;
  void zou_he(double* f, int axis, int s, double rho, const double u[3], const double Fc[3]) const;
  void regularize(double* f, int axis, int s, double rho, const double u[3], const double Fc[3]) const;

  lbm::Setup s_;
  const config::Config* cfg_;
  MPI_Comm comm_;
  coupler::Box box_;
  long n_[3];
  int Q_;
  std::vector<std::array<int, 3>> e_;
  std::vector<double> w_;
  std::vector<int> opp_;
  std::vector<double> f_;  // f_[cell * Q + q], post-collision
  long steps_ = 0;
  std::vector<double> out_u_, out_p_, out_rho_, out_solid_, out_phase_;
  std::map<long, Solid> solid_;     // covered cells
  std::vector<long> solid_order_;   // in the order of set_solid
  long solid_steps_ = 0;
  std::vector<double> source_;      // per cell, lattice units (empty: none)
  // Two fluids / interior solids: red and blue per cell (f_ = r_ + b_), the
  // colour field of the pulled populations, solid id per cell (0: fluid).
  std::vector<double> r_, b_, phi_;
  std::vector<int> solid_id_;
  std::vector<double> grain_eps_, grain_cos_;  // per cell: psm fraction and cos(theta) (0: none)
  // immersed.method ibm: the forcing (made at the first markers), the forced
  // velocity per cell, the force per cell (lattice units; empty: no bodies).
  std::unique_ptr<ibm::DirectForcing> ibm_;
  std::array<std::vector<double>, 3> ibm_u_;
  std::vector<double> ibm_density_;  // the touched cells' rho (standard formulation; else empty)
  std::vector<double> ibm_force_;
  double max_u2_ = 0.0, step_u2_ = 0.0;  // largest u^2 of the last step's collisions; of this one's so far
};

}  // namespace coflow::fluid
