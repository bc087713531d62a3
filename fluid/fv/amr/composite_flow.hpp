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
// Boundaries: periodic, or no-slip walls (optionally moving tangentially:
// a lid) on the non-periodic domain faces, where the face velocity is zero
// and dp/dn = 0. Inlets, outlets, the fv solver's boundary keys and IMEX
// diffusion come with its wiring into `fluid.solver: fv` (issue 25).
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "fluid/fv/amr/composite_faces.hpp"
#include "fluid/fv/amr/ij_system.hpp"

namespace coflow::fluid::fv::amr {

class CompositeFlow {
 public:
  // The forest keeps at least dims + 1 components per cell: the velocity,
  // then the pressure (kinematic), then any the caller uses (a refinement
  // criterion's field). Periodic axes, walls on the others.
  CompositeFlow(Forest& forest, const GridGeometry& geometry, double viscosity);
  ~CompositeFlow();

  const CompositeGrid& grid() const { return *grid_; }
  // The velocity of the wall on domain face 2 axis + (side > 0) (tangential;
  // zero until set).
  void set_wall_velocity(int face, const std::array<double, 3>& v) {
    walls_[static_cast<std::size_t>(face)] = v;
  }
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
  // The total momentum sum V u along `axis` over all ranks.
  double momentum(int axis) const;
  int last_iterations() const { return iterations_; }
  // A momentum source per local cell and component (acceleration, the
  // point particles' force over the cell's fluid mass: seed 003 eq. 3.43),
  // held over the following steps; empty: none.
  void set_source(std::vector<std::vector<double>> acceleration) { source_ = std::move(acceleration); }

 private:
  using Field = std::vector<std::vector<double>>;  // per component, per local cell
  Field read_velocity() const;
  void write(const Field& u);
  Field with_ghosts(const Field& u);  // per component, per slot
  Field rates(const Field& u);        // advection and diffusion of u
  void project(Field& u, double dt, int stage);
  double volume(long c) const;
  const std::array<double, 3>& wall(const SubFace& f) const {
    return walls_[static_cast<std::size_t>(2 * f.axis + (f.side > 0))];
  }
  void build();  // the grid, faces and Poisson system of the forest as it is

  Forest& forest_;
  GridGeometry geometry_;
  std::unique_ptr<CompositeGrid> grid_;
  std::vector<std::vector<SubFace>> faces_;  // ids as slots
  std::vector<std::vector<double>> mac_;     // per local cell, per sub-face: the velocity along +axis
  std::unique_ptr<IjSystem> poisson_;
  std::vector<std::vector<double>> source_;
  std::array<std::array<double, 3>, 6> walls_{};
  // Per local cell, the last pressure of each stage and of the initial
  // projection: each solve's initial guess.
  std::array<std::vector<double>, 3> phi_;
  double nu_;
  int dims_;
  int nc_;  // values per cell on the forest
  int iterations_ = 0;
};

}  // namespace coflow::fluid::fv::amr
