// The fluid component's interface. A variant is a class behind it, picked once
// from `fluid.solver` (see fluid/variants.cpp).
#pragma once

#include <mpi.h>

#include <array>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "coflow/config.hpp"
#include "coflow/decomposition.hpp"
#include "coflow/output.hpp"
#include "coflow/reproducible_sum.hpp"
#include "coflow/run_config.hpp"
#include "fluid/params.hpp"
#include "immersed/ibm/markers.hpp"

namespace coflow::fluid {

using config::Vec3;

// Global diagnostics, reduced over the component (SI units).
struct Diagnostics {
  double mass = 0.0;
  Vec3 momentum{0, 0, 0};
  double kinetic_energy = 0.0;
  double max_velocity = 0.0;
  double max_mach = 0.0;
  std::vector<double> extra;  // the values of FluidSolver::series_columns(), in order
};

class FluidSolver {
 public:
  struct Setup {
    const config::Config& cfg;
    const FluidParams& params;
    coupler::Decomposition decomposition;
    int rank = 0;
    MPI_Comm comm = MPI_COMM_NULL;
    double time_step = 0.0;  // s: the step the coupling window asks for; 0: the method's own
  };

  virtual ~FluidSolver() = default;

  // The solver's natural step in s (0: none, the solver can jump to any time).
  virtual double time_step() const = 0;
  // Advance by dt (a whole number of the solver's steps).
  virtual void advance(double dt) = 0;
  virtual double time() const = 0;
  virtual long steps() const = 0;

  // Owned block of this rank.
  virtual const coupler::Box& owned() const = 0;
  // Fields for snapshots, as arrays over owned() (no ghost), `components` per cell.
  virtual std::vector<output::GridField> fields(const config::StringList& names) = 0;
  // A solver whose own grid is not the uniform one (fv's adaptive grid)
  // writes it next to each snapshot, with the fields `names` (those of
  // fields()): <dir>/<stem>.h5 and .xmf. Collective.
  virtual void write_levels(const std::string& dir, const std::string& stem, double time, long step,
                            const config::StringList& names) {
    (void)dir, (void)stem, (void)time, (void)step, (void)names;
  }
  virtual Diagnostics diagnostics() = 0;  // collective
  // Columns of series/fluid.csv after the common ones (Diagnostics::extra).
  virtual std::vector<output::Series::Column> series_columns() const { return {}; }

  // Checkpoint and restart (collective): the complete state, so that a restarted
  // run continues bit for bit.
  // Partially saturated cells (immersed method psm, Noble & Torczynski 1998):
  // the owned cells covered by solids (index (k ny + j) nx + i in the owned
  // block), their solid fraction, solid velocity (m/s, 3 per cell) and
  // wetting (cos of the red fluid's contact angle on the grains; used by a
  // two-phase fluid). They hold until the next call. A solver without PSM throws.
  virtual void set_solid(std::span<const long> cells, std::span<const double> fraction,
                         std::span<const double> velocity, std::span<const double> wetting) {
    (void)cells, (void)fraction, (void)velocity, (void)wetting;
    throw std::runtime_error("this fluid solver does not support partially saturated cells (immersed.method psm)");
  }
  // The force (N, 3 per cell of the last set_solid) that the fluid exerted on
  // the solid in each of those cells, averaged over the steps since the last call
  // (seed 000 eq. 2.70 before the sum over cells).
  virtual void take_solid_force(std::vector<double>& force) { force.clear(); }
  // Momentum source of point particles (immersed method point, seed 003 eq.
  // 3.43): a force density (N/m^3, 3 per owned cell) added to the body force
  // until the next call. A solver that cannot take it throws.
  virtual void set_source(std::span<const double> force_density) {
    (void)force_density;
    throw std::runtime_error("this fluid solver does not take momentum sources (immersed.method point)");
  }

  // Immersed boundaries (immersed.method ibm, seed 003 §4.2.1): the markers
  // of the bodies, held until the next call; the solver iterates the
  // multi-direct forcing in each of its steps. A solver without it throws.
  virtual void set_markers(ibm::MarkerSet markers) {
    (void)markers;
    throw std::runtime_error("this fluid solver does not take immersed boundaries (immersed.method ibm)");
  }
  // Per body the force (N) and torque about its reference point (N m) the
  // fluid exerted on it, the mean over the steps since the last call; then the
  // most forcing iterations of a step and the largest slip (m/s) they left.
  virtual std::vector<double> take_body_loads() { return {}; }

  // The impulse (N s, 3 per face x- ... z+, then 3 per interior solid) this
  // rank's fluid gave the wall faces and solids since the last call, relative
  // to the reference pressure, as exact sums (1 rank gives the bits of N);
  // empty for a solver that does not keep it (series/fluid_walls.csv is then
  // not written).
  virtual coupler::ExactSums take_wall_impulse() { return coupler::ExactSums(0); }
  virtual bool keeps_wall_impulse() const { return false; }

  virtual void save(const std::string& dir) = 0;
  virtual void load(const std::string& dir, long steps, double time) = 0;
};

}  // namespace coflow::fluid
