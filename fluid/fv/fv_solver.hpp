// fv: incompressible Navier-Stokes by finite volumes on a staggered (MAC)
// grid (seed 003 §4.1): velocity components on the faces of the fluid grid's
// cells, pressure at their centres; advection explicit (central or bounded
// upwind-biased, divergent or non-divergent form), diffusion implicit (IMEX
// SBDF2 or CNAB2 with a variable step from the CFL condition, seed 003 eqs.
// 4.1-4.2); an incremental pressure-correction projection (Chorin 1968). The
// linear systems go to hypre's Struct multigrid-preconditioned conjugate
// gradients on the fluid's blocks (MPI).
//
// Storage: on the blocks of fluid/grid with two ghost layers; u_c at index
// (i, j, k) is the velocity through the lower c-face of cell (i, j, k). A
// rank at the upper end of a non-periodic axis c keeps the domain's boundary
// face in its first ghost layer.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "fluid/fluid_solver.hpp"
#include "fluid/fv/lines.hpp"
#include "fluid/fv/params.hpp"
#include "fluid/fv/poisson_multigrid.hpp"
#include "fluid/fv/scheme.hpp"
#include "fluid/fv/speed_bounds.hpp"
#include "fluid/fv/struct_system.hpp"
#include "fluid/grid/ghost_exchange.hpp"
#include "fluid/turbulence_params.hpp"
#include "immersed/ibm/direct_forcing.hpp"

namespace coflow::fluid {

class FvSolver final : public FluidSolver {
 public:
  using Params = fv::FvParams;
  FvSolver(const Setup& setup, const Params& params);
  ~FvSolver() override;

  double time_step() const override { return 0.0; }  // variable: any window, in CFL-limited steps
  void advance(double dt) override;
  double time() const override { return time_; }
  long steps() const override { return steps_; }
  const coupler::Box& owned() const override { return blk_.owned; }
  std::vector<output::GridField> fields(const config::StringList& names) override;
  Diagnostics diagnostics() override;
  std::vector<output::Series::Column> series_columns() const override;
  // The arrays over the owned cells that named_fields hands out by name.
  struct Arrays {
    std::span<const double> u, p, rho, div, k, eps, nut, y_plus;
  };
  static std::vector<output::GridField> named_fields(const config::StringList& names, const Arrays& a);
  static Diagnostics cell_diagnostics(const std::vector<double>& centre_velocity, double cell_mass);
  static void reduce(Diagnostics& d, MPI_Comm comm);  // a rank's sums to the component's (collective)
  // The columns fv adds to series/fluid.csv (fv-reference adds the same).
  static std::vector<output::Series::Column> columns(bool turbulent = false);  // with k-epsilon's when turbulent
  // k_mean, epsilon_mean, nu_t_max, y_plus_max and the model's effort per
  // step (`effort`: its column's name), as fv and its adaptive variant write them.
  static std::vector<output::Series::Column> turbulence_columns(const std::string& effort);
  void set_source(std::span<const double> force_density) override;
  void set_markers(ibm::MarkerSet markers) override;
  std::vector<double> take_body_loads() override;
  void save(const std::string& dir) override;
  void load(const std::string& dir, long steps, double time) override;

  // The work done so far on this rank (bench-fv): wall seconds in the steps and
  // in the pressure Poisson and viscous solves, Poisson solves and iterations.
  struct Work {
    long steps = 0, poisson_solves = 0, poisson_iterations = 0;
    double step_s = 0, poisson_s = 0, viscous_s = 0, ibm_s = 0;
  };
  Work work() const {
    return {steps_,        poisson_solves_,  poisson_iteration_sum_,
            step_seconds_, poisson_seconds_, viscous_seconds_, ibm_seconds_};
  }

 private:
  // A face of the box: how the velocity and pressure behave there.
  struct Face {
    // dirichlet: wall, velocity; open: pressure, outflow; symmetry: no flow through, no shear.
    enum Kind { periodic, dirichlet, open, symmetry } kind = periodic;
    Vec3 velocity{0, 0, 0};
    double pressure = 0.0;
    double ramp = 0.0;
    bool here = false;             // this rank's block touches it
    bool convective = false;       // an outflow face: du/dt + U du/dn = 0
    bool wall = false;             // a dirichlet face with no normal velocity (a wall, moving or not)
    bool profiled = false;         // a velocity face with a profile (parabolic, table or expression)
    BoundaryParams boundary;       // its keys: the profile's factor (profile_factor)
    Vec3 velocity_at(double t) const;
    double pressure_at(double t) const;
  };
  using Field = std::vector<double>;  // over the padded block
  using Faces = std::array<Field, 3>;

  // What lies beyond one side of an unknown face along an axis.
  enum class Neighbour { inside, wall_normal, wall_tangential, open };

  void initialise();
  void step(double dt);
  double stable_step();  // collective; sets velocity_scale_; throws on a value that is not finite
  // Ghosts (boundaries.cpp).
  void fill_ghosts(Faces& u, double t);
  void fill_face_ghosts(Field& u, int c, int a, int side, const Face& f, double t,
                        bool top_face = false) const;
  void fill_pressure_ghosts(Field& p, double t, bool increment, double t0);
  void extrapolate_open_faces(Faces& u, double dt);
  double outflow_speed(int face) const;
  // A domain face of axis c: not an unknown (inline: in every face loop).
  bool is_boundary_face(int c, long i) const {
    if (periodic_[c]) return false;
    const long g = blk_.owned.lo[c] + i;
    return g == 0 || g == cells_[c];
  }
  bool is_dirichlet_face(int c, long i) const;
  double profile(int face, int c, const long* x, double t) const;
  // Momentum (momentum.cpp).
  void advection(const Faces& u, Faces& out) const;
  template <int DIMS, bool UPWIND, bool DIVERGENT>
  void advection_row(const Faces& u, int c, long n0, long len, double* out) const;
  // What lies beyond the side of the unknown u_c at `at` along d: another
  // unknown (inside the domain or across a periodic face), a wall's or velocity
  // face's value (on the face for d == c, a ghost for d != c; a symmetry face's
  // normal component is 0), or no gradient (an open face; a symmetry face for
  // the tangential components). Inline:
  // the implicit viscous matrices are rebuilt from it every step.
  Neighbour neighbour_kind(int c, const long* at, int d, int side) const {
    if (periodic_[d]) return Neighbour::inside;
    const long g = blk_.owned.lo[d] + at[d];
    const bool beyond =
        d == c ? (side == 0 ? g - 1 == 0 : g + 1 == cells_[d]) : (side == 0 ? g == 0 : g + 1 == cells_[d]);
    if (!beyond) return Neighbour::inside;
    const Face::Kind kind = faces_[static_cast<std::size_t>(2 * d + side)].kind;
    if (d == c) return kind == Face::open ? Neighbour::open : Neighbour::wall_normal;
    return kind == Face::dirichlet ? Neighbour::wall_tangential
                                   : Neighbour::open;  // open, symmetry: no gradient
  }
  double rhs_terms(int c, long n, const fv::Imex& s, double dt, double w_now, double w_last) const;
  double viscous_rhs(int c, const long* at, long n, const fv::Imex& s, double dt) const;
  void viscous_rhs_inside(int c, long n0, long o0, long len, const fv::Imex& s, double dt);
  void momentum(const fv::Imex& s, double dt);
  void set_viscous(int c, double diag, double theta);
  void viscous_rows_inside(int c, double diag_scale, const double (&w)[3], long n, long o, long len,
                           fv::StructSystem::Rows& m) const;
  // Projection (projection.cpp).
  double divergence_at(const Faces& u, long n) const;
  void make_poisson(const coupler::Decomposition& dec, const std::array<bool, 3>& per);
  void set_poisson();
  void poisson_rhs(double factor, double t0, double t1, bool incremental);
  std::array<double, 2> guess_weights(double dt) const;
  void project(const fv::Imex& s, double dt, bool incremental);
  double max_divergence(const Faces& u) const;  // collective

  // Immersed boundaries (immersed_boundary.cpp): u* forced after the
  // predictor (immersed.ibm.stage after_predictor), or the force found on the
  // explicit estimate of u* and added to the predictor's rows (in_predictor).
  void force_immersed(const fv::Imex& s, double dt);
  void force_in_predictor(const fv::Imex& s, double dt);

  // Turbulence, k-epsilon with the two-layer wall model (turbulence/*.cpp).
  void init_turbulence();
  void set_body_wall_distance(const ibm::MarkerSet& markers);  // wall_y_: the box's walls and the bodies
  void turbulence_step(double dt);
  template <int DIMS>
  void source_row(double* const (&out)[4], long n0, long len, double (&umax)[3]) const;
  // A scalar entering through each domain face (x-, x+, y-, y+, z-, z+), per
  // line of cells across it (fv::for_lines; at() reads the line's two
  // coordinates across the face): one value where the face's k and epsilon
  // are uniform, one per line where they follow the inlet's speed.
  struct FaceLines {
    std::array<std::vector<double>, 6> values;
    // The index of line (0, 0) and the stride of the face's second axis;
    // per_line false: values[f] holds the face's one value.
    std::array<long, 6> first{}, stride{};
    std::array<bool, 6> per_line{};
    double at(int f, const long* line) const {
      const auto i = static_cast<std::size_t>(f);
      const std::vector<double>& v = values[i];
      if (!per_line[i]) return v[0];
      const int a = f / 2;
      return v[static_cast<std::size_t>(first[i] + line[(a + 1) % 3] + line[(a + 2) % 3] * stride[i])];
    }
  };
  void set_inlet_lines(double t);
  // Advection of k and epsilon (turbulence/scalar_advection.cpp).
  int scalar_substeps(double (&umax)[3], double dt) const;
  void scalar_faces(const Field& q, const FaceLines& inlet, const bool (&inflow)[6], int d,
                    Field& face) const;
  template <int DIMS>
  void advect_scalar_row(const double* q, const double* const (&face)[3], double h, double* next, long n0,
                         long len) const;
  void advect_scalar(Field& q, const FaceLines& inlet, double wall_sign, double dt, int sub);
  void solve_scalar(fv::StructSystem& sys, Field& q, Field& change, const Field& sink, const Field& source,
                    double sigma, const FaceLines& inlet, bool wall_zero, const Field* fixed, double dt);
  // What the rows of one scalar's system read (solve_scalar): padded fields
  // (fixed null without fixed cells) and the constants.
  struct ScalarRows {
    const double *q, *change, *sink, *source, *fixed;
    double half_sigma, inv_dt;
    const FaceLines* inlet;
    bool wall_zero;
    double inv_h2[3];
  };
  template <int DIMS, bool FIXED>
  void assemble_scalar_row(const ScalarRows& in, fv::StructSystem::Rows& m, const bool (&edge)[3][2], long n0,
                           long o0, long len);
  template <int DIMS>
  static int diagonally_dominant(const fv::StructSystem::Rows& m, long o0, long len);
  void add_scalar_face_terms(const ScalarRows& in, fv::StructSystem::Rows& m, const bool (&edge)[3][2],
                             const long* at, long n0, long o0, long len);
  void fill_scalar_ghosts(Field& q, const FaceLines& inlet, double wall_sign, bool extrapolate);
  void update_eddy_viscosity();
  // `stepped`: the values came from a step (a loss of positivity is then a
  // bug), else from the input or a checkpoint (`hint` names it).
  void check_positive(double t, const std::string& hint, bool stepped) const;
  // f(face, at, n) for each owned cell next to a wall face of this rank (the
  // face's owned lines only): y+ and the wall functions.
  template <class F>
  void for_wall_cells(F&& f) const {
    for (int face = 0; face < 2 * dims_; ++face) {
      const Face& w = faces_[static_cast<std::size_t>(face)];
      if (!w.here || !w.wall) continue;
      const int a = face / 2;
      const long first = face % 2 == 0 ? 0 : blk_.extent[a] - 1;
      fv::for_lines(blk_, a, [&](auto index, const long* line) {
        long at[3] = {line[0], line[1], line[2]};
        for (int b = 0; b < 3; ++b)
          if (b != a && (at[b] < 0 || at[b] >= blk_.extent[b])) return;  // a halo line
        at[a] = first;
        f(face, static_cast<const long*>(at), static_cast<long>(index(first)));
      });
    }
  }
  // wall: log-law (turbulence/wall_functions.cpp).
  double wall_speed(int f, const long* at, long n, double t) const;
  void wall_function_ghosts();
  void wall_function_production(Field& production) const;
  void wall_function_epsilon(Field& fixed);
  // nu + nu_t on side `side` along d of u_c's control volume (u_c at index n,
  // the lower c-face of cell n): along c the cell below (n - s_c) or the cell
  // n itself; along another axis the edge between the four cells around it.
  // Inline: the implicit viscous matrices are rebuilt from it every step.
  double nu_face(int c, long n, int d, int side) const {
    if (!turbulent_) return nu_;
    const long sc = stride(c);
    if (d == c) return nu_ + nut_[side == 0 ? n - sc : n];
    // The edge's four cells summed in one order whichever side it is seen
    // from (a the pair below it along d, b the pair above): the matrix is
    // symmetric to the bit (StructSystem's matvec reads half the couplings).
    const long a = side == 0 ? n - stride(d) : n, b = a + stride(d);
    return nu_ + 0.25 * ((nut_[a] + nut_[a - sc]) + (nut_[b] + nut_[b - sc]));
  }
  double diffusion_at(const Field& u, int c, long n) const;
  template <int DIMS, int C>
  void stress_transpose_row(const Faces& u, long n0, long len, double* out) const;
  void add_stress_transpose(const Faces& u, Faces& out) const;
  std::vector<double> y_plus() const;
  void add_turbulence_diagnostics(Diagnostics& d);

  long stride(int d) const { return d == 0 ? 1 : d == 1 ? blk_.padded(0) : blk_.padded(0) * blk_.padded(1); }
  // f(at, n, o) over the owned cells: owned-relative coordinates, padded and owned index.
  template <class F>
  void for_owned(F&& f) const {
    long o = 0, at[3];
    for (at[2] = 0; at[2] < blk_.extent[2]; ++at[2])
      for (at[1] = 0; at[1] < blk_.extent[1]; ++at[1])
        for (at[0] = 0; at[0] < blk_.extent[0]; ++at[0], ++o)
          f(static_cast<const long*>(at), blk_.idx(at[0], at[1], at[2]), o);
  }
  // f(at, n, o, len) for each row of owned cells along x: `at` the row's
  // first cell (owned-relative), n and o its padded and owned index; the
  // row's cells are n + i and o + i, i < len (a loop over i vectorises).
  template <class F>
  void for_owned_rows(F&& f) const {
    long o = 0, at[3] = {0, 0, 0};
    for (at[2] = 0; at[2] < blk_.extent[2]; ++at[2])
      for (at[1] = 0; at[1] < blk_.extent[1]; ++at[1], o += blk_.extent[0])
        f(static_cast<const long*>(at), blk_.idx(0, at[1], at[2]), o, blk_.extent[0]);
  }
  // Over the owned rows of u_c's unknowns: cell(at, n, o) for each unknown
  // that may see a domain face, inside(n0, o0, len) for the run of a row whose
  // neighbours are all unknowns (along x only the first two and the last two
  // can see one); with `split` false every unknown goes to cell.
  template <class Cell, class Inside>
  void for_unknown_rows(int c, bool split, Cell&& cell, Inside&& inside) const {
    for_owned_rows([&](const long* at, long n0, long o0, long len) {
      bool in = split && len > 4 && !(c > 0 && is_boundary_face(c, at[c]));
      for (int d = 1; d < dims_ && in; ++d)
        in = neighbour_kind(c, at, d, 0) == Neighbour::inside &&
             neighbour_kind(c, at, d, 1) == Neighbour::inside;
      const long first = in ? 2 : len, last = in ? len - 2 : len;
      long here[3] = {0, at[1], at[2]};
      for (here[0] = 0; here[0] < first; ++here[0])
        cell(static_cast<const long*>(here), n0 + here[0], o0 + here[0]);
      if (in) inside(n0 + first, o0 + first, last - first);
      for (here[0] = last; here[0] < len; ++here[0])
        cell(static_cast<const long*>(here), n0 + here[0], o0 + here[0]);
    });
  }
  template <class F>
  void for_padded(F&& f) const {
    long at[3];
    for (at[2] = -blk_.ghost[2]; at[2] < blk_.extent[2] + blk_.ghost[2]; ++at[2])
      for (at[1] = -blk_.ghost[1]; at[1] < blk_.extent[1] + blk_.ghost[1]; ++at[1])
        for (at[0] = -blk_.ghost[0]; at[0] < blk_.extent[0] + blk_.ghost[0]; ++at[0])
          f(static_cast<const long*>(at), blk_.idx(at[0], at[1], at[2]));
  }
  std::vector<double> owned_of(const Field& f) const;
  void set_owned(Field& f, const std::vector<double>& v) const;

  const config::Config& cfg_;
  FluidParams fluid_;
  Params p_;
  MPI_Comm comm_;
  int rank_ = 0;
  grid::GhostExchange ex_;
  grid::Block blk_;
  coupler::Index3 cells_;
  std::array<bool, 3> periodic_{};
  int dims_ = 3;
  double h_[3] = {1, 1, 1};
  double inv_h_[3] = {1, 1, 1};  // 1 / h_: the k-epsilon loops multiply (a division was a fifth of them)
  double nu_ = 0, rho_ = 1;
  std::array<Face, 6> faces_;
  bool has_open_ = false;
  double velocity_scale_ = 0.0;  // the largest |u_c| at the last step's start
  // The speeds the CFL step allows for beside the fluid's own (speed_bounds.hpp):
  // the velocity faces', and the immersed markers' over a window.
  std::array<double, 3> boundary_speed_{0.0, 0.0, 0.0}, marker_speed_{0.0, 0.0, 0.0};
  fv::MarkerSpeeds markers_speed_;  // of the last set of markers
  bool first_window_ = false;       // the run's first window (steps_ == 0 at its start)

  Faces u_, u_old_, ustar_, adv_, adv_old_, source_,
      source_old_;  // source: at the cells, the last step's too
  // The velocity through an open upper face of axis c, kept at the owned cell
  // below it (index n - 1 along c) so that the ghost exchange carries it to
  // the blocks beside; fill_ghosts copies it to the boundary face (index n).
  Faces top_;
  Field p_field_, phi_, phi_old_;  // the pressure, its last increment and the one before
  std::vector<double> rhs_, x_;
  std::unique_ptr<fv::StructSystem> poisson_;         // hypre's PCG + PFMG or SMG, or
  std::unique_ptr<fv::PoissonMultigrid> poisson_mg_;  // coflow's geometric multigrid (fluid.fv.multigrid)
  std::array<std::unique_ptr<fv::StructSystem>, 3> viscous_;
  std::array<double, 3> viscous_key_{0, 0, 0},
      viscous_theta_{0, 0, 0};  // a0/dt and theta nu of the matrices set
  bool have_source_ = false, source_fresh_ = false;  // fresh: set since the last step

  double time_ = 0.0, dt_prev_ = 0.0, dt_prev2_ = 0.0;  // the last step and the one before
  double next_time_ = 0.0;  // the time the step under way reaches
  long steps_ = 0;
  // Of the last window: steps, the last step, the largest Poisson iterations
  // and the largest divergence after projection.
  long window_steps_ = 0;
  int poisson_iterations_ = 0, viscous_iterations_ = 0;
  double last_dt_ = 0.0, max_divergence_ = 0.0;
  double step_seconds_ = 0.0, poisson_seconds_ = 0.0, viscous_seconds_ = 0.0;  // wall time, this rank
  long poisson_solves_ = 0, poisson_iteration_sum_ = 0;
  std::vector<double> out_u_, out_p_, out_rho_, out_div_, out_k_, out_eps_, out_nut_, out_yplus_;

  // fluid.turbulence: k, epsilon and nu_t at the cells (padded), each cell's
  // distance to the nearest wall (infinite without walls; the box's walls
  // and the immersed bodies' surfaces), the implicit systems of k and epsilon.
  bool turbulent_ = false;
  bool log_law_ = false;  // wall: log-law, the wall functions
  TurbulenceParams turb_;
  FluidParams::FaceTurbulence inlets_;  // what enters through each face (FluidParams::inlet_turbulence)
  FaceLines inlet_k_, inlet_eps_, inlet_nut_;  // k, epsilon and nu_t entering, at the time of set_inlet_lines
  Field k_, eps_, nut_, wall_y_, box_wall_y_;
  Field k_change_, eps_change_;  // the last step's change by the k and epsilon solves (next first guesses)
  std::unique_ptr<fv::StructSystem> k_system_, eps_system_;
  int turbulence_iterations_ = 0;
  double turbulence_seconds_ = 0.0, scalar_solve_seconds_ = 0.0;  // wall time, this rank
  std::array<Field, 8> scratch_;                                  // the turbulence step's work fields
  std::vector<double> row_work_;  // a row's work space (fv::Closure::nu_t_row)
  fv::StructSystem::Rows rows_;   // a matrix being assembled (momentum, k, epsilon)

  // immersed.method ibm: the multi-direct forcing, made at the first markers.
  std::unique_ptr<ibm::DirectForcing> ibm_;
  bool ibm_in_predictor_ = false;  // immersed.ibm.stage in_predictor
  bool ibm_in_rhs_ = false;        // rhs_terms adds a0/dt ibm_du_ (the force of this step)
  Faces ibm_du_;                   // in_predictor: the forcing's change of the estimate of u*
  double ibm_seconds_ = 0.0;  // wall time, this rank
};

}  // namespace coflow::fluid
