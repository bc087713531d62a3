// Prescribed flow fields for component tests and one-way coupled runs.
#pragma once

#include "fluid/analytic/params.hpp"
#include "fluid/fluid_solver.hpp"

namespace coflow::fluid {

// Snyder & Lumley's decay laws, seed 003 eqs 5.21-5.22: the mean-square streamwise
// fluctuation (w' in the seed) and lateral fluctuation v' as functions of
// xi = x/M. The second lateral component equals v' (seed 003 §5.4), so
// k = (w'^2 + 2 v'^2) / 2; epsilon = -U dk/dx (eq. 5.23).
struct GridDecay {
  double U, M;
  double streamwise2(double xi) const { return U * U / (42.4 * (xi - 16.0)); }
  double lateral2(double xi) const { return U * U / (39.4 * (xi - 12.0)); }
  double k(double xi) const { return 0.5 * (streamwise2(xi) + 2.0 * lateral2(xi)); }
  // dk/dx = (1/M) dk/dxi; each term c/(xi - x0) has derivative -c/(xi - x0)^2.
  double dk_dx(double xi) const {
    return -0.5 * (streamwise2(xi) / (xi - 16.0) + 2.0 * lateral2(xi) / (xi - 12.0)) / M;
  }
  double epsilon(double xi) const { return -U * dk_dx(xi); }
};

class AnalyticFluid final : public FluidSolver {
 public:
  using Params = AnalyticParams;
  AnalyticFluid(const Setup& setup, const Params& params);

  double time_step() const override { return 0.0; }
  void advance(double dt) override;
  double time() const override { return time_; }
  long steps() const override { return steps_; }
  const coupler::Box& owned() const override { return owned_; }
  std::vector<output::GridField> fields(const config::StringList& names) override;
  Diagnostics diagnostics() override;
  // Prescribed fields: particles do not act back (one-way coupling).
  void set_source(std::span<const double>) override {}
  void save(const std::string&) override {}  // the state is the time
  void load(const std::string&, long steps, double time) override {
    steps_ = steps;
    time_ = time;
    evaluate();
  }

  // The prescribed velocity at a point and time.
  Vec3 velocity_at(const Vec3& x, double t) const;
  double pressure_at(const Vec3& x, double t) const;
  Vec3 vorticity_at(const Vec3& x, double t) const;
  // Turbulence kinetic energy k (m^2/s^2) and its dissipation rate epsilon (m^2/s^3);
  // zero except for grid-turbulence.
  double k_at(const Vec3& x) const;
  double epsilon_at(const Vec3& x) const;

 private:
  void evaluate();
  const config::Config& cfg_;
  FluidParams fluid_;
  Params p_;
  MPI_Comm comm_;
  coupler::Box owned_;
  double time_ = 0.0;
  long steps_ = 0;
  std::vector<double> u_, p_field_, rho_, omega_, k_, eps_;
};

}  // namespace coflow::fluid
