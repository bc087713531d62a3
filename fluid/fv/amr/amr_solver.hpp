// fv on the block-structured adaptive grid (`fluid.solver: fv` with
// `fluid.fv.refinement`; seed 003 §4.1.1): the composite flow of
// composite_flow.hpp on a p4est forest, regridded every few steps by the
// criteria of the configuration, behind the fluid's interface.
//
// domain.cells is the uniform grid of the finest level. The coupler, the
// snapshots' uniform fields and the probes see that grid, cut into the
// fluid's blocks (uniform_view.hpp): each fine cell shows the value of the
// leaf cell that holds it, and a point particles' momentum source (seed 003
// eq. 3.43) returns to the leaf cells as the mean over their fine cells, so
// it lands in the finest cell holding the particle and sum V f is kept. Each
// snapshot also writes the composite grid itself, one XDMF grid per level
// (<snapshot>_levels.xmf). With fluid.turbulence the k-epsilon model runs on
// the composite grid (composite_turbulence.hpp) after each step of the flow.
#pragma once

#include <memory>
#include <vector>

#include "fluid/fluid_solver.hpp"
#include "fluid/fv/amr/composite_flow.hpp"
#include "fluid/fv/amr/composite_turbulence.hpp"
#include "fluid/fv/amr/uniform_view.hpp"
#include "fluid/fv/params.hpp"
#include "fluid/fv/speed_bounds.hpp"
#include "immersed/ibm/direct_forcing.hpp"

namespace coflow::fluid::fv::amr {

class AmrFvSolver final : public FluidSolver {
 public:
  using Params = fv::FvParams;
  AmrFvSolver(const Setup& setup, const Params& params);
  ~AmrFvSolver() override;

  double time_step() const override { return 0.0; }  // variable: any window, in CFL-limited steps
  void advance(double dt) override;
  double time() const override { return time_; }
  long steps() const override { return steps_; }
  const coupler::Box& owned() const override { return owned_; }
  std::vector<output::GridField> fields(const config::StringList& names) override;
  void write_levels(const std::string& dir, const std::string& stem, double time, long step,
                    const config::StringList& names) override;
  Diagnostics diagnostics() override;
  std::vector<output::Series::Column> series_columns() const override;
  void set_source(std::span<const double> force_density) override;
  // Immersed boundaries (seed 003 §4.2.1) on the finest level: the leaves
  // around the markers refine to it first (the `bodies` criterion), then the
  // multi-direct forcing runs on the finest cells in each Heun stage.
  void set_markers(ibm::MarkerSet markers) override;
  std::vector<double> take_body_loads() override;
  void save(const std::string& dir) override;
  void load(const std::string& dir, long steps, double time) override;

  const CompositeGrid& grid() const { return flow_->grid(); }

 private:
  ForestSpec forest_spec() const;
  void make_flow();        // the flow on forest_, with the configuration's boundaries
  void set_initial();      // the configuration's initial velocity and pressure on the leaves
  void after_regrid();     // the uniform view and the source on the new leaves
  void apply_source();     // body force and particle source, as accelerations per leaf cell
  void set_turbulence_inlets();  // k and epsilon entering through the faces (CompositeTurbulence::set_inlets)
  std::vector<int> marks();
  // Points a marker's kernel reaches: the marker and +-2.5 finest cells along
  // each axis (3^d points; no leaf of 4 or more cells lies between them).
  std::vector<std::array<double, 3>> marker_reach() const;
  void make_forcing();        // the forcing's stencils on the current leaves; checks they are all finest
  void install_forcing();     // from the first markers on
  void force(CompositeFlow::Field& u, double dt, int stage);
  void regrid();
  double stable_step();    // collective; throws on a value that is not finite
  std::vector<double> cell_values(int first, int count, double scale) const;  // from the forest, per local cell
  double& value(std::size_t cell, int q) const;  // the forest's component q of local cell `cell`

  const config::Config& cfg_;
  FluidParams fluid_;
  Params p_;
  MPI_Comm comm_;
  int rank_ = 0;
  coupler::Decomposition decomposition_;
  coupler::Box owned_;
  int dims_ = 3;
  double h_ = 1.0;  // the finest cells' edge
  double rho_ = 1.0, nu_ = 0.0;
  GridGeometry geometry_;
  std::unique_ptr<Forest> forest_;
  std::unique_ptr<CompositeFlow> flow_;
  std::unique_ptr<CompositeTurbulence> turbulence_;  // with fluid.turbulence
  // Per leaf cell on the forest: the velocity, the kinematic pressure, a
  // criterion's field, then with turbulence k, epsilon and nu_t.
  int components() const { return dims_ + (fluid_.turbulence.on ? 5 : 2); }
  int turbulence_first() const { return dims_ + 2; }
  std::unique_ptr<UniformView> view_;
  std::vector<double> source_fine_;   // N/m^3, 3 per owned fine cell: the last set_source
  std::vector<double> source_cells_;  // the same per local leaf cell

  double time_ = 0.0, dt_prev_ = 0.0, last_dt_ = 0.0;
  long steps_ = 0, window_steps_ = 0, regrids_ = 0;
  int poisson_iterations_ = 0;  // the most of a step in the window
  int turbulence_substeps_ = 0;  // the most of a step in the window (k and epsilon's transport)
  // Where the time went, for the log (bench-amr reads it): the steps, the
  // regrids between them, and the cells summed over the steps.
  double step_seconds_ = 0.0, regrid_seconds_ = 0.0, cell_steps_ = 0.0;
  std::unique_ptr<ibm::DirectForcing> ibm_;
  std::unique_ptr<ibm::MarkerSet> markers_;  // the last set, for the stencils after a regrid
  double velocity_scale_ = 0.0;              // the largest |u| at the last step's start
  std::array<double, 3> boundary_speed_{0.0, 0.0, 0.0};  // the velocity faces' (speed_bounds.hpp)
  bool first_window_ = false;                            // the run's first window
  std::vector<double> out_u_, out_p_, out_rho_, out_div_, out_zero_;
  std::array<std::vector<double>, 4> out_turbulence_;  // k, epsilon, nu_t, y_plus
};

}  // namespace coflow::fluid::fv::amr
