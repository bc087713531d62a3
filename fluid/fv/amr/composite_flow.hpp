// Incompressible Navier-Stokes on the composite grid (seed 003 §4.1 on the
// refined grid of §4.1.1): velocities at cell centres kept on the forest's
// leaves, advected and diffused by fluxes through the composite faces
// (composite_faces.hpp, so momentum is conserved across levels), stepped
// explicitly by Heun's second-order Runge-Kutta method with all levels on
// one step, and projected at each stage. The projection is exact on the
// faces: face-normal velocities interpolated from the cells are corrected by
// the same face gradients the composite Laplacian is built from (L = D G),
// so their discrete divergence vanishes to the solver's tolerance (the
// staggered, MAC, velocities); the cell velocities take the gradient by
// Gauss's theorem from the same faces (an approximate projection, Almgren,
// Bell & Szymczak 1996), and the face velocities carry the advection.
//
// Boundaries: periodic, or on the non-periodic domain faces no-slip walls
// (optionally moving tangentially: a lid), inlets (velocity given, dp/dn =
// 0), outlets (p = 0, du/dn = 0) and symmetry faces (no flow through, no
// shear). amr_solver.hpp maps fluid.boundaries onto them. Diffusion is
// explicit, or implicit (set_implicit_diffusion): an IMEX form of the same
// Heun step, backward Euler in the predictor and the trapezoidal rule
// (Crank-Nicolson) in the corrector, each a composite Helmholtz system per
// velocity component (GMRES + BoomerAMG), so that the step is not held to the
// explicit diffusive limit h^2 / (4 d nu) on the finest cells.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "fluid/fv/amr/composite_faces.hpp"
#include "fluid/fv/amr/composite_laplacian.hpp"
#include "fluid/fv/amr/ij_system.hpp"

namespace coflow::fluid::fv::amr {

class CompositeFlow {
 public:
  // The forest keeps at least dims + 1 components per cell: the velocity,
  // then the pressure (kinematic), then any the caller uses (a refinement
  // criterion's field). Periodic axes, walls on the others.
  // `solve`: where the projection's Poisson (GMRES + BoomerAMG) stops.
  CompositeFlow(Forest& forest, const GridGeometry& geometry, double viscosity,
                IjSystem::Options solve = {1e-12, 300});
  ~CompositeFlow();

  const CompositeGrid& grid() const { return *grid_; }
  // What holds on domain face 2 axis + (side > 0) where its axis is not
  // periodic: a no-slip wall (the default; moving tangentially at the
  // velocity set here), an inlet (the velocity `inflow` gives at each face
  // centre), or an outlet (pressure 0, zero normal derivative of the
  // velocity). Set before the first projection.
  enum class Boundary { wall, inlet, outlet, symmetry };
  using Inflow = std::function<std::array<double, 3>(const std::array<double, 3>&)>;
  void set_wall_velocity(int face, const std::array<double, 3>& v) {
    set_wall_velocity(face, [v](const std::array<double, 3>&) { return v; });
  }
  // A wall sliding at a velocity that varies along it (a profile with no
  // normal component): still a wall for the turbulence model and y+.
  void set_wall_velocity(int face, Inflow v) { walls_[static_cast<std::size_t>(face)] = std::move(v); }
  void set_inlet(int face, Inflow inflow);
  void set_outlet(int face);
  // A symmetry face: no flow through it, no shear along it (dp/dn = 0).
  void set_symmetry(int face);
  // Called in each Heun stage on the predicted velocity (per component, per
  // local cell) before its projection: an immersed boundary's direct forcing
  // (seed 003 eqs. 4.8-4.11). Stage 0 predicts u1 = u0 + dt r0; stage 1 is
  // u2 = (u0 + u1 + dt r1) / 2, so a velocity change dU made in stage 0 enters
  // the step as dU / 2 and one made in stage 1 as dU (explicit diffusion;
  // implicit: stage_weight()).
  using Field = std::vector<std::vector<double>>;  // per component, per local cell
  void set_forcing(std::function<void(Field& u, double dt, int stage)> forcing) { forcing_ = std::move(forcing); }
  // The weight a stage's velocity change has in the step: explicit, 1/2 for
  // stage 0 and 1 for stage 1 (above); implicit, 1 for both (the corrector
  // starts from the forced predictor's change in full, as from its pressure).
  double stage_weight(int stage) const { return stage == 0 && !implicit_ ? 0.5 : 1.0; }
  // Implicit diffusion (see above); set before the first step.
  void set_implicit_diffusion(bool on) { implicit_ = on; }
  // Projects the velocity held by the forest (call once after setting it).
  void project_initial();
  // One step of length dt (Heun: two stages, each projected).
  void step(double dt);
  // Regrids the forest by `marks` (less the coarsenings balance would undo:
  // keep_coarsening_balanced; Forest::adapt carries the velocity
  // conservatively), rebuilds the operators and projects the carried
  // velocity. Collective. Returns false (and keeps the operators) where no
  // leaf was refined or coarsened.
  bool regrid(std::vector<int> marks);
  // The vorticity's magnitude per cell (2D: |dv/dx - du/dy|) into the
  // forest's `component` (a refinement criterion: mark_by_magnitude).
  void vorticity(int component);
  // Checkpoint (collective): the forest (leaves, velocity, pressure) in
  // dir/forest.p4est, the face velocities and each stage's last pressure in
  // dir/flow.h5; a flow built on Forest(comm, spec, dir + "/forest.p4est")
  // then load(dir) continues bit for bit on the same rank count (on another,
  // to the Poisson solver's tolerance).
  void save(const std::string& dir);
  void load(const std::string& dir);
  // The largest |divergence| of the face velocities, after the last projection.
  double face_divergence() const;
  // Per local cell, the divergence of its face velocities (1/s).
  std::vector<double> divergence() const;
  // The eddy viscosity (k-epsilon, composite_turbulence.hpp) held in the
  // forest's `component` (-1: none): the viscous stress through a face then
  // takes nu + nu_t at the face (its value stencil, the same bits from both
  // sides: conservative) and the cells take (grad u)^T . grad nu_t, the
  // stress's transposed part d/dx_d (nu_t d u_d / dx_c) for a divergence-free
  // u (seed 003 eq. 3.12), explicit. With implicit diffusion the Helmholtz
  // systems take nu + nu_t per face, built again at each step. nu_t is zero
  // on walls, the cell's own on the other domain faces (boundary_eddy).
  void set_eddy_viscosity(int component) { eddy_ = component; }
  // The velocity gradient d u_q / d x_a per local cell ([q][a]), by Gauss's
  // theorem over its faces (the walls' and inlets' imposed values on theirs).
  using Gradient = std::array<std::array<double, 3>, 3>;
  std::vector<Gradient> velocity_gradients();
  // What the turbulence model reads: the faces (their stencils emptied: the
  // flow holds them flat), the face-normal velocities of the last projection
  // (along +axis), each local cell's spacing, and what holds on each domain face.
  const std::vector<std::vector<SubFace>>& faces() const { return faces_; }
  // At cell c's sub-face s.
  double normal_velocity(std::size_t c, std::size_t s) const { return mac_[face_begin_[c] + s]; }
  double spacing(std::size_t c) const { return h_[c]; }
  Boundary boundary(int face) const { return kinds_[static_cast<std::size_t>(face)]; }
  // The total momentum sum V u along `axis` over all ranks.
  double momentum(int axis) const;
  int last_iterations() const { return iterations_; }
  // A momentum source per local cell and component (acceleration, the
  // point particles' force over the cell's fluid mass: seed 003 eq. 3.43),
  // held over the following steps; empty: none.
  void set_source(std::vector<std::vector<double>> acceleration) { source_ = std::move(acceleration); }

 private:
  Field read_velocity() const;
  void write(const Field& u);
  Field with_ghosts(const Field& u);  // per component, per slot
  // Advection and diffusion of u (and the source); for the implicit step the
  // diffusion goes to *viscous (apart), or is not computed (none).
  enum class Viscous { included, apart, none };
  Field rates(const Field& u, Viscous part = Viscous::included, Field* viscous = nullptr);
  std::vector<Gradient> gradients(const Field& g) const;  // g: the velocity with ghosts
  // (grad u)^T . grad nu_t per cell and component (g: the velocity, nut: nu_t, both with ghosts).
  Field stress_transpose(const Field& g, const std::vector<double>& nut) const;
  void step_implicit(double dt);
  // u -= dt G p at the cells, G by Gauss's theorem over their faces (p per slot).
  void subtract_gradient(Field& u, const std::vector<double>& p, double dt) const;
  // Solves (1 - theta dt nu L_q) x = b for each component q (x: the guess in,
  // the solution out), b holding the right-hand side less the boundary values'
  // part, which this adds; `which`: 0 predictor, 1 corrector (a system each).
  void solve_viscous(Field& b, Field& x, double theta_dt, std::size_t which);
  std::vector<std::vector<double>> face_viscosity() const;  // nu + nu_t per cell and sub-face
  // nu_t on cell c's domain face f: 0 on a wall, the cell's own on inlets,
  // outlets and symmetry faces (zero normal gradient; nut per slot).
  double boundary_eddy(const SubFace& f, std::size_t c, const std::vector<double>& nut) const {
    return kinds_[face_of(f)] == Boundary::wall ? 0.0 : nut[c];
  }
  void project(Field& u, double dt, int stage);
  void check_closed_balance(const std::vector<double>& b, double dt) const;
  void solve_pressure(const std::vector<double>& b, std::vector<double>& phi, double dt, int stage,
                      bool solved_before);
  double volume(long c) const;
  // The velocity component q at cell c's domain face f (fields with ghosts).
  double wall_velocity(const SubFace& f, std::size_t c, const Field& g, std::size_t q) const;
  std::vector<double> pressure() const;  // per local cell, from the forest
  void set_pressure(const std::vector<double>& p);
  static std::size_t face_of(const SubFace& f) { return static_cast<std::size_t>(2 * f.axis + (f.side > 0)); }
  // The velocity a wall, inlet or symmetry face imposes on cell c's boundary
  // face f (g: the velocity with ghosts; a symmetry face reads the cell's).
  std::array<double, 3> imposed(const SubFace& f, std::size_t c, const Field& g) const;
  bool outlet(const SubFace& f) const { return kinds_[face_of(f)] == Boundary::outlet; }
  void build();  // the grid, faces and Poisson system of the forest as it is
  void flatten_faces();

  // faces_ laid out flat for the loops of every step (the same faces in the
  // same order, their stencils in two arrays instead of a heap block each;
  // faces_ keeps the rest, its stencils emptied once copied): the operators take the same
  // operations in the same order (the bits may differ only where the compiler
  // fuses a multiply-add differently). Cell c's faces are
  // flat_[face_begin_[c]] .. [face_begin_[c + 1] - 1].
  struct FlatFace {
    int axis;
    int side;
    double fraction;
    bool wall;
    // Into stencil_slot_, stencil_weight_: the value's stencil, then the
    // gradient's from value_end (32 bytes a face).
    std::uint32_t value_begin, value_end, gradient_end;
  };
  double flat_value(const FlatFace& f, const std::vector<double>& field) const {
    return flat_evaluate(f.value_begin, f.value_end, field);
  }
  double flat_gradient(const FlatFace& f, const std::vector<double>& field) const {
    return flat_evaluate(f.value_end, f.gradient_end, field);
  }
  // evaluate() (composite_grid.hpp) on the flat stencils: the same sum in the same order.
  double flat_evaluate(std::uint32_t begin, std::uint32_t end, const std::vector<double>& field) const {
    double v = 0.0;
    for (std::uint32_t k = begin; k < end; ++k) v += stencil_weight_[k] * field[stencil_slot_[k]];
    return v;
  }
  std::vector<std::size_t> face_begin_;
  std::vector<FlatFace> flat_;
  std::vector<std::size_t> stencil_slot_;
  std::vector<double> stencil_weight_;

  Forest& forest_;
  GridGeometry geometry_;
  std::unique_ptr<CompositeGrid> grid_;
  std::vector<std::vector<SubFace>> faces_;  // ids as slots
  std::vector<double> h_;                    // per local cell, its spacing
  std::vector<double> mac_;                  // per sub-face (flat_'s order): the velocity along +axis
  std::unique_ptr<IjSystem> poisson_;
  // Implicit diffusion: per component its Laplacian (the conditions its
  // boundaries impose on it), and its Helmholtz systems for the predictor
  // (theta 1) and the corrector (theta 1/2) at the step they were built for.
  bool implicit_ = false;
  std::vector<CompositeLaplacian> viscous_;
  std::vector<std::vector<SubFace>> global_faces_;  // faces_ with ids, for the eddy viscosity's operators
  std::array<std::array<std::unique_ptr<IjSystem>, 2>, 3> helmholtz_;
  std::array<std::array<double, 2>, 3> helmholtz_dt_{};
  std::vector<std::vector<double>> source_;
  std::array<Inflow, 6> walls_;      // a wall's velocity at a point of it (none: at rest)
  std::array<Boundary, 6> kinds_{};  // all walls
  std::array<Inflow, 6> inflow_;
  std::function<void(Field&, double, int)> forcing_;
  // Per local cell, the last pressure of each stage and of the initial
  // projection; and each stage's rate of change between its last two solves
  // (empty until a stage has been solved twice on this grid). A stage's
  // guess is phi_ + dt phi_rate_: its pressure extrapolated linearly in time.
  std::array<std::vector<double>, 3> phi_;
  std::array<std::vector<double>, 2> phi_rate_;
  double nu_;
  int dims_;
  int nc_;              // values per cell on the forest
  IjSystem::Options solve_;  // where the Poisson solves stop
  bool pinned_ = true;  // no outlet: the pressure of global cell 0 is held at 0
  int eddy_ = -1;       // the forest's component holding nu_t (-1: none)
  int iterations_ = 0;
};

}  // namespace coflow::fluid::fv::amr
