// lbm: the production lattice Boltzmann solver. Structure-of-arrays
// populations with one ghost layer, fused pull-stream-collide over two arrays,
// MPI block decomposition with the halo exchange overlapped with the interior,
// no allocation per step.
#pragma once

#include <memory>
#include <array>
#include <functional>
#include <span>
#include <stdexcept>

#include "fluid/fluid_solver.hpp"
#include "immersed/ibm/direct_forcing.hpp"
#include "fluid/lbm/params.hpp"
#include "fluid/lbm/setup.hpp"

namespace coflow::fluid {

// The lattice- and formulation-specific core, picked once at construction.
class LbmCore {
 public:
  virtual ~LbmCore() = default;
  virtual void step() = 0;
  virtual void macroscopic(std::vector<double>& u, std::vector<double>& rho) const = 0;  // owned cells
  virtual double max_u2() const = 0;  // of the last step, this rank
  virtual void set_max_u2(double u2) = 0;    // a restart's (the immersed boundaries' scale in its first step)
  virtual long first_nonfinite() const = 0;  // owned cell index or -1
  virtual int q() const = 0;
  // Owned cells' populations, cell after cell (x fastest), q innermost.
  virtual void get_populations(std::vector<double>& out) const = 0;
  virtual void set_populations(const std::vector<double>& in) = 0;
  // The rest weights w_q that the stored populations are offset by (one fluid:
  // zero-centred, g = f - w, collision.hpp), or none where they are f itself
  // (two fluids, and lbm-reference's): a checkpoint says which it holds.
  virtual std::vector<double> stored_offset() const { return {}; }
  // Collide the listed owned cells of the last step as partially saturated
  // cells (lattice units: us per cell), adding each cell's fluid momentum gain
  // sum_q B Omega^s_q e_q to `gain` (3 per cell). The step left these cells
  // (set_psm) except those on open faces, which it collided and psm() leaves.
  virtual void psm(std::span<const long> cells, std::span<const double> fraction, std::span<const double> us,
                   std::span<double> gain) = 0;
  // The partially saturated cells of the next steps, before them, for a core
  // whose step needs them (the two-phase core colours them by their grains'
  // wetting, cos(theta) per cell).
  virtual void set_psm(std::span<const long> cells, std::span<const double> fraction,
                       std::span<const double> wetting) {
    (void)cells, (void)fraction, (void)wetting;
  }
  // Per-cell force density added to the body force (lattice units, 3 per owned
  // cell; empty: none). Rows holding a source take the per-cell path.
  virtual void set_source(std::span<const double> force) = 0;
  // Immersed boundaries (immersed.method ibm): `hook` runs in every step once
  // the populations have streamed (halos and walls filled) and before any
  // cell collides; in it, streamed_velocity gives the listed owned cells'
  // velocity (j + F/2) / rho_m with the body force and the source, and
  // set_cell_forces adds a force (lattice units, 3 per cell) to those cells
  // for this step's collision. A core without them throws.
  virtual void set_hook(std::function<void()> hook) {
    (void)hook;
    throw std::runtime_error("this lattice Boltzmann fluid does not take immersed boundaries");
  }
  virtual void streamed_velocity(std::span<const long> cells, std::span<double> u, std::span<double> rho) const {
    (void)cells, (void)u, (void)rho;
  }
  virtual void set_cell_forces(std::span<const long> cells, std::span<const double> force) { (void)cells, (void)force; }
  // The momentum each wall face (3 per face, x- ... z+) and each interior
  // solid (3 per solid of fluid.solids, in order) took since the last call,
  // times `unit`, this rank's cells' as exact sums; zeroed.
  virtual coupler::ExactSums take_wall_momentum(double unit) = 0;
  // Owned cells' colour fraction (rho_r - rho_b) / (rho_r + rho_b) and solid
  // mask (1 in interior solids); false: one fluid, no solids (all red, fluid).
  virtual bool phase(std::vector<double>& out) const {
    (void)out;
    return false;
  }
  virtual bool solid_mask(std::vector<double>& out) const {
    (void)out;
    return false;
  }
  // Owned cells' grain fraction as the two-fluid collision takes it (set_psm's,
  // 0 where it leaves a grain out: next to open faces and in solids); false:
  // no grains in this core's two-fluid step.
  virtual bool grain_fractions(std::vector<double>& out) const {
    (void)out;
    return false;
  }
};

class LbmSolver final : public FluidSolver {
 public:
  using Params = lbm::LbmParams;
  LbmSolver(const Setup& setup, const Params& params);

  double time_step() const override { return s_.units.dt; }
  void advance(double dt) override;
  double time() const override { return steps_ * s_.units.dt; }
  long steps() const override { return steps_; }
  const coupler::Box& owned() const override { return owned_; }
  std::vector<output::GridField> fields(const config::StringList& names) override;
  Diagnostics diagnostics() override;
  std::vector<output::Series::Column> series_columns() const override;
  void save(const std::string& dir) override;
  void load(const std::string& dir, long steps, double time) override;
  void set_solid(std::span<const long> cells, std::span<const double> fraction, std::span<const double> velocity,
                 std::span<const double> wetting) override;
  void take_solid_force(std::vector<double>& force) override;
  void set_source(std::span<const double> force_density) override;
  void set_markers(ibm::MarkerSet markers) override;
  std::vector<double> take_body_loads() override;
  coupler::ExactSums take_wall_impulse() override;
  bool keeps_wall_impulse() const override { return true; }

  const lbm::Setup& setup() const { return s_; }

 private:
  std::string fastest_cell() const;           // collective
  std::string mach_advice(double mach) const;
  std::string source_diagnosis() const;       // collective
  void force_immersed();                       // the core's hook (immersed_boundary.cpp)
  std::vector<double> source_si_;  // the point particles' momentum source, N/m^3, 3 per owned cell
  lbm::Setup s_;
  const config::Config* cfg_ = nullptr;
  MPI_Comm comm_;
  coupler::Box owned_;
  std::unique_ptr<LbmCore> core_;
  long steps_ = 0;
  bool mach_warned_ = false;
  std::vector<double> out_u_, out_rho_, out_p_, out_solid_, out_phase_;
  std::vector<double> out_grain_;  // the psm grains' fraction of each owned cell, for the phase series
  // PSM: covered cells, fraction, solid velocity (lattice units), and the fluid's
  // momentum gain summed over the steps since the last take_solid_force().
  std::vector<long> solid_cells_;
  std::vector<double> solid_fraction_, solid_us_, solid_gain_;
  long solid_steps_ = 0;
  // immersed.method ibm: the forcing (made at the first markers) on the cell
  // centres, the velocity at the cells it touches (lattice units, 3 arrays
  // over the owned cells) and their velocity before it, density and forces.
  std::unique_ptr<ibm::DirectForcing> ibm_;
  std::array<std::vector<double>, 3> ibm_u_;
  std::vector<double> ibm_at_, ibm_rho_, ibm_force_;
  std::vector<double> ibm_density_;  // the touched cells' rho (standard formulation; else empty)
};

}  // namespace coflow::fluid
