// fv-reference: the finite-volume fluid of fv written as plainly as possible,
// serial, the oracle for fv. The same discretisation (staggered grid, the
// same face values, wall closure, IMEX coefficients and projection), but its
// own loops and ghosts and its own linear solver: unpreconditioned conjugate
// gradients on operators applied cell by cell (no matrix, no multigrid).
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <stdexcept>
#include <vector>

#include "fluid/fluid_solver.hpp"
#include "fluid/fv/params.hpp"
#include "fluid/fv/scheme.hpp"
#include "fluid/fv/speed_bounds.hpp"
#include "fluid/turbulence_params.hpp"
#include "immersed/ibm/direct_forcing.hpp"

namespace coflow::fluid {

class FvReference final : public FluidSolver {
 public:
  using Params = fv::FvParams;
  FvReference(const Setup& setup, const Params& params);

  double time_step() const override { return 0.0; }
  void advance(double dt) override;
  double time() const override { return time_; }
  long steps() const override { return steps_; }
  const coupler::Box& owned() const override { return box_; }
  std::vector<output::GridField> fields(const config::StringList& names) override;
  Diagnostics diagnostics() override;
  std::vector<output::Series::Column> series_columns() const override;
  void set_source(std::span<const double> force_density) override;
  void set_markers(ibm::MarkerSet markers) override;
  std::vector<double> take_body_loads() override;
  void save(const std::string& dir) override;
  void load(const std::string& dir, long steps, double time) override;

 private:
  using Field = std::vector<double>;  // cells with two ghost layers on each axis of more than one cell
  using Faces = std::array<Field, 3>;
  enum class Kind {
    periodic,
    wall,
    open,
    symmetry
  };  // wall: wall or velocity face; open: pressure or outflow
  struct Side {
    Kind kind = Kind::periodic;
    Vec3 velocity{0, 0, 0};
    double pressure = 0.0, ramp = 0.0;
    BoundaryParams boundary;                 // its keys: a velocity face's profile (profile_factor)
    bool pressure_face = false;              // open: a pressure face (else an outflow face)
  };

  long at(long i, long j, long k) const { return ((k + g_[2]) * m_[1] + (j + g_[1])) * m_[0] + (i + g_[0]); }
  long at(const long x[3]) const { return at(x[0], x[1], x[2]); }
  long step_of(int d) const { return d == 0 ? 1 : d == 1 ? m_[0] : m_[0] * m_[1]; }
  template <class F>
  void each_cell(F&& f) const;  // f(x, n) over the cells
  void velocity_maxima(double umax[3]) const;  // the largest |u_c| on the faces; throws on one not finite
  template <class F>
  void for_lines(int a, F&& f) const;
  Vec3 side_velocity(int face, double t) const;
  double side_pressure(int face, double t) const;
  bool unknown(int c, long i) const;  // the face of u_c at index i along c is solved for
  double profile(int face, int c, const long* x, double t) const;

  // Ghosts of the velocity at time t. keep_open: the normal velocity on an
  // open face stays (else it becomes the first face inside's); zero: the faces'
  // values taken as zero (the linear part of an operator).
  void velocity_ghosts(Faces& u, double t, bool keep_open, bool zero) const;
  // Periodic copies; zero gradient at walls; the face's value open_value[f]
  // on open faces (a ghost at 2 value - p).
  void pressure_ghosts(Field& p, const double open_value[6]) const;
  double divergence_at(const Faces& u, long n) const;
  void correct(Faces& u, double factor) const;
  bool convect_outflow(Faces& star, double dt) const;
  double advection_at(const Faces& u, int c, long n) const;
  double laplacian_at(const Field& q, long n) const;
  double predictor_rhs(int c, const long* x, long n, const fv::Imex& s, double dt, bool with_pressure,
                       bool deferred) const;
  void momentum(const fv::Imex& s, double dt, bool with_pressure);
  void solve_predictor(int c, const fv::Imex& s, double dt, Field rhs, Faces& star);
  void project(const fv::Imex& s, double dt, bool incremental);
  void force_immersed(Faces& star, const fv::Imex& s, double dt);  // immersed_boundary_reference.cpp
  double wall_weight(int c, const long x[3], long n) const;
  template <class Value>
  double deferred_wall(int c, const long x[3], long n, double theta, Value&& value) const;
  void wrap_cells(Faces& f) const;
  // k-epsilon (k_epsilon_reference.cpp): fv's turbulence/ written plainly.
  bool is_inlet(int face) const;  // a velocity face with flow through it (else a wall)
  void turbulence_init();
  void turbulence_step(double dt);
  // What enters through face f (x-, x+, y-, ...) beside the cell x (x along
  // f's axis not read): k, epsilon or nu_t (inlet_value).
  using FaceValues = std::function<double(int f, const long* x)>;
  FaceValues inlet(int q) const {
    return [this, q](int f, const long* x) { return inlet_value(q, f, x); };
  }
  double inlet_value(int q, int face, const long* x) const;
  void scalar_ghosts(Field& q, const FaceValues& inlet, double wall_sign, bool extrapolate) const;
  void eddy_viscosity();
  double nu_at(int c, long n, int d, int side) const;  // nu + nu_t on a side of u_c's control volume
  double viscous_at(const Field& q, int c, long n) const;  // div((nu + nu_t) grad u_c)
  double stress_transpose_at(const Faces& u, int c, long n) const;
  double strain_rate2_at(long n) const;
  void advect_scalar(Field& q, const FaceValues& inlet, double wall_sign, double dt) const;
  void solve_scalar(Field& q, const Field& sink, const Field& source, double sigma, const FaceValues& inlet,
                    bool wall_zero, const std::vector<char>* fixed, double dt, const char* what) const;
  std::vector<double> y_plus() const;
  // wall: log-law (fv's turbulence/wall_functions.cpp): f(face, x, n) over
  // the cells next to each wall; the speed there along the wall at time t.
  template <class F>
  void for_wall_cells(F&& f) const;
  double wall_speed(int face, const long* x, std::size_t n, double t) const;
  void wall_function_epsilon(std::vector<char>& fixed);
  // Conjugate gradients for A x = b over the listed indices; A applied by `apply`.
  template <class Apply>
  void conjugate_gradients(Apply&& apply, const std::vector<long>& rows, Field& x, const Field& b,
                           const char* what, double floor = 0.0) const;

  MPI_Comm comm_;
  const config::Config& cfg_;
  FluidParams fluid_;
  Params opt_;
  coupler::Box box_;
  long n_[3] = {1, 1, 1}, g_[3] = {0, 0, 0}, m_[3] = {1, 1, 1};
  int dims_ = 3;
  double h_[3] = {1, 1, 1}, nu_ = 0, rho_ = 1;
  Side sides_[6];
  bool has_open_ = false;
  Faces u_, u_old_, adv_, adv_old_, source_, source_old_;  // source: at the cells, the last step's too
  Field p_, phi_, phi_old_;  // phi_old_: the increment before the last, for the checkpoint only
  double time_ = 0.0, dt_prev_ = 0.0, dt_prev2_ = 0.0, last_dt_ = 0.0, next_time_ = 0.0;
  double velocity_scale_ = 0.0;  // the largest |u_c| at the step's start
  // The velocity faces' and the markers' speeds, which the CFL step allows for (fv's).
  std::array<double, 3> boundary_speed_{0.0, 0.0, 0.0}, marker_speed_{0.0, 0.0, 0.0};
  fv::MarkerSpeeds markers_speed_;  // of the last set of markers
  bool first_window_ = false;       // the run's first window
  long steps_ = 0, window_steps_ = 0;
  int poisson_iterations_ = 0;
  std::unique_ptr<ibm::DirectForcing> ibm_;  // immersed.method ibm: made at the first markers
  std::string ibm_stage_;                    // immersed.ibm.stage: after_predictor | in_predictor
  std::vector<double> out_u_, out_p_, out_rho_, out_div_, out_k_, out_eps_, out_nut_, out_yplus_;
  bool turbulent_ = false;
  bool log_law_ = false;  // wall: log-law
  TurbulenceParams turb_;
  FluidParams::FaceTurbulence inlets_;  // what enters through each face
  double inlet_time_ = 0.0;             // the time of the inlets' velocity (ramps, profiles in t)
  Field k_, eps_, nut_, wall_y_;  // cells, padded; wall_y_: distance to the nearest wall
  Field box_wall_y_;              // the same, the box's walls alone (immersed bodies are walls too)
};

// The loops and the solver shared by fv_reference.cpp and k_epsilon_reference.cpp.

// f(o, x) for each line along axis a of the padded grid, o (x) its cell at index 0 along a.
template <class F>
void FvReference::for_lines(int a, F&& f) const {
  for (long k = -g_[2]; k < n_[2] + g_[2]; ++k)
    for (long j = -g_[1]; j < n_[1] + g_[1]; ++j)
      for (long i = -g_[0]; i < n_[0] + g_[0]; ++i) {
        const long x[3] = {i, j, k};
        if (x[a] == 0) f(at(x), static_cast<const long*>(x));
      }
}

template <class F>
void FvReference::each_cell(F&& f) const {
  for (long k = 0; k < n_[2]; ++k)
    for (long j = 0; j < n_[1]; ++j)
      for (long i = 0; i < n_[0]; ++i) {
        const long x[3] = {i, j, k};
        f(x, static_cast<std::size_t>(at(x)));
      }
}

template <class Apply>
void FvReference::conjugate_gradients(Apply&& apply, const std::vector<long>& rows, Field& x, const Field& b,
                                      const char* what, double floor) const {
  Field r(x.size(), 0.0), d(x.size(), 0.0), Ad(x.size(), 0.0);
  apply(x, Ad);
  double rr = 0.0, bb = 0.0;
  for (long i : rows) {
    const auto I = static_cast<std::size_t>(i);
    r[I] = b[I] - Ad[I];
    d[I] = r[I];
    rr += r[I] * r[I];
    bb += b[I] * b[I];
  }
  if (!std::isfinite(bb + rr))
    throw std::runtime_error(fmt::format("fv-reference: the {}'s right-hand side is not finite", what));
  if (bb == 0.0) {  // as hypre: the solution of A x = 0 is 0
    for (long i : rows) x[static_cast<std::size_t>(i)] = 0.0;
    return;
  }
  const double stop = std::max(opt_.tolerance * opt_.tolerance * bb, floor * floor);
  const long limit = 20 * static_cast<long>(rows.size()) + 100;
  for (long it = 0; rr > stop; ++it) {
    if (it == limit)
      throw std::runtime_error(
          fmt::format("fv-reference: the {} did not converge in {} iterations", what, limit));
    apply(d, Ad);
    double dAd = 0.0;
    for (long i : rows) dAd += d[static_cast<std::size_t>(i)] * Ad[static_cast<std::size_t>(i)];
    const double alpha = rr / dAd;
    double rr_new = 0.0;
    for (long i : rows) {
      const auto I = static_cast<std::size_t>(i);
      x[I] += alpha * d[I];
      r[I] -= alpha * Ad[I];
      rr_new += r[I] * r[I];
    }
    for (long i : rows)
      d[static_cast<std::size_t>(i)] =
          r[static_cast<std::size_t>(i)] + rr_new / rr * d[static_cast<std::size_t>(i)];
    if (!std::isfinite(rr_new))
      throw std::runtime_error(fmt::format("fv-reference: the {} broke down (a residual not finite)", what));
    rr = rr_new;
  }
}

}  // namespace coflow::fluid
