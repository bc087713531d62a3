// fv-reference: the finite-volume fluid of fv written as plainly as possible,
// serial, the oracle for fv. The same discretisation (staggered grid, the
// same face values, wall closure, IMEX coefficients and projection), but its
// own loops and ghosts and its own linear solver: unpreconditioned conjugate
// gradients on operators applied cell by cell (no matrix, no multigrid).
#pragma once

#include <array>
#include <vector>

#include "fluid/fluid_solver.hpp"
#include "fluid/fv/params.hpp"
#include "fluid/fv/scheme.hpp"

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
    bool shaped[3] = {false, false, false};  // a parabolic velocity face: the axes its profile spans
    bool pressure_face = false;              // open: a pressure face (else an outflow face)
  };

  long at(long i, long j, long k) const { return ((k + g_[2]) * m_[1] + (j + g_[1])) * m_[0] + (i + g_[0]); }
  long at(const long x[3]) const { return at(x[0], x[1], x[2]); }
  long step_of(int d) const { return d == 0 ? 1 : d == 1 ? m_[0] : m_[0] * m_[1]; }
  template <class F>
  void each_cell(F&& f) const;  // f(x, n) over the cells
  template <class F>
  void for_lines(int a, F&& f) const;
  Vec3 side_velocity(int face, double t) const;
  double side_pressure(int face, double t) const;
  bool unknown(int c, long i) const;  // the face of u_c at index i along c is solved for
  double profile(int face, int c, const long* x) const;

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
  void momentum(const fv::Imex& s, double dt, bool with_pressure);
  void project(const fv::Imex& s, double dt, bool incremental);
  double wall_weight(int c, const long x[3]) const;
  void wrap_cells(Faces& f) const;
  // Conjugate gradients for A x = b over the listed indices; A applied by `apply`.
  template <class Apply>
  void conjugate_gradients(Apply&& apply, const std::vector<long>& rows, Field& x, const Field& b,
                           const char* what) const;

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
  Field p_, phi_;
  double time_ = 0.0, dt_prev_ = 0.0, last_dt_ = 0.0, next_time_ = 0.0;
  long steps_ = 0, window_steps_ = 0;
  int poisson_iterations_ = 0;
  std::vector<double> out_u_, out_p_, out_rho_, out_div_;
};

}  // namespace coflow::fluid
