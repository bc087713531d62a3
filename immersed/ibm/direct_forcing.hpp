// Multi-direct forcing on the fluid's side (seed 003 §4.2.1, eqs. 4.8-4.11;
// Uhlmann 2005; Wang, Fan & Luo 2008). The immersed component sends the
// markers (ibm/markers.hpp); the fluid iterates here, inside its step, with no
// message to the immersed component per iteration:
//   U_m   = sum_x D_h(x - X_m) u*(x) dx dy dz                     (eq. 4.9)
//   dU_m  = U_b(X_m) - U_m        (eq. 4.8: F_m = alpha2 rho dU_m / dt)
//   u*(x) += sum_m D_h(x - X_m) dU_m Delta V_m                    (eqs. 4.10-4.11)
// until max_m |dU_m| falls below the tolerance (the multi-direct part), or
// the same equations for all markers at once by conjugate gradients. The
// velocity lives on `components` grids of points (a staggered grid: one per
// component, each offset by half a cell off its own axis). A rank sums its own
// points; the markers' interpolated velocities are summed over the ranks (one
// reduction per iteration: 3 doubles per marker, and the terms of the
// stencils that lie on several ranks, so that every rank sums each stencil
// in the same order as one rank would: the same bits on any number of
// ranks), so every rank computes the same dU_m and spreads it into its own
// points.
#pragma once

#include <mpi.h>

#include <array>
#include <functional>
#include <vector>

#include "immersed/ibm/kernels.hpp"
#include "immersed/ibm/markers.hpp"

namespace coflow::ibm {

struct ForcingParams {
  Kernel kernel = Kernel::hat;
  int max_iterations = 20;
  double tolerance = 1e-4;  // of the velocity scale
  bool conjugate_gradients = false;  // else the seed's repeated direct forcing
};

class DirectForcing {
 public:
  // A component's points: offset (in cells, per axis) of point (0, 0, 0) from
  // the grid's lower corner, and where a point's value is stored on this rank
  // (-1: not this rank's, or not an unknown, e.g. a boundary face).
  struct Points {
    std::array<double, 3> offset{0.5, 0.5, 0.5};
    std::function<long(const std::array<long, 3>& global)> index;
  };
  struct Grid {
    GridGeometry geometry;
    std::array<bool, 3> periodic{false, false, false};
    std::vector<Points> components;  // dims of them
  };
  struct Result {
    int iterations = 0;
    double slip = 0.0;  // m/s: the largest |U_b - U_m| after the iterations
  };

  DirectForcing(Grid grid, ForcingParams params, MPI_Comm comm);
  // A staggered (MAC) grid: u_c on the lower c-faces of the cells; index(c, g)
  // where the face g of u_c is stored, or -1.
  static Grid staggered(const GridGeometry& g, std::array<bool, 3> periodic,
                        std::function<long(int c, const std::array<long, 3>& global)> index);
  // A collocated grid (lbm): every component at the cell centres, stored alike.
  static Grid collocated(const GridGeometry& g, std::array<bool, 3> periodic,
                         std::function<long(const std::array<long, 3>& global)> index);

  // New markers (each window when a body moves, once when none does).
  void set_markers(MarkerSet markers);
  // The grid's velocity unit in m/s (lbm: dx / dt): the markers' velocities
  // (m/s) are divided by it where they meet the grid's; 1 by default.
  void set_velocity_unit(double unit) { unit_ = unit; }
  // The markers placed at time t (apply does it too) and the storage indices
  // their stencils touch on this rank, each once (any component).
  void prepare(double t) { place(t); }
  const std::vector<long>& touched() const { return touched_; }
  bool empty() const { return set_.markers.empty(); }
  // Forces u (one array per component) toward the markers' velocities at time
  // t (the markers moved on at constant acceleration from their set's time).
  // `scale` is the flow's velocity scale for the tolerance; the load on the bodies is
  // accumulated as -factor sum_m dU_m Delta V_m over `dt` (factor: the
  // fluid's alpha2 rho / dt, so that factor dU is the force density of eq. 4.8).
  // `density`, where the fluid's density varies (lbm's standard formulation:
  // a cell takes the force factor rho dU), is the density relative to the
  // one in `factor` at the grid's points, stored where every component is (a
  // collocated grid); each marker's load then takes it interpolated with the
  // marker's kernel, so that the bodies take exactly the opposite of the
  // fluid's force. Null: a constant density.
  Result apply(const std::array<double*, 3>& u, double t, double scale, double factor, double dt,
               const double* density = nullptr);
  // Per body: force (N) and torque about its centre (N m) on the body, the
  // mean over the steps since the last call; then the sums restart.
  std::vector<double> take_loads();
  // take_loads() followed by the most iterations and the largest slip (m/s)
  // since the last call: what the fluid sends back (FluidSolver::take_body_loads).
  std::vector<double> take_report();

 private:
  struct Entry {
    long index;
    double weight;
  };
  void place(double t);
  void build_stencils();
  void lay_out_split();
  Result iterate_mdf(const std::array<double*, 3>& u, double scale, std::vector<double>& total);
  Result solve_cg(const std::array<double*, 3>& u, double scale, std::vector<double>& total);
  double slip(const std::vector<double>& at, std::vector<double>& b) const;
  void apply_operator(const std::vector<double>& x, std::vector<double>& q);
  void interpolate(const std::array<double*, 3>& u, std::vector<double>& out) const;
  void spread(const std::array<double*, 3>& u, const std::vector<double>& du) const;
  void add_loads(const std::vector<double>& total, double factor, double dt, const double* density);

  Grid grid_;
  ForcingParams p_;
  MPI_Comm comm_;
  int dims_;
  MarkerSet set_;
  std::vector<Vec> x_;       // the markers' positions at the last place()
  std::vector<Vec> target_;  // and their velocities there
  double placed_at_ = -1.0;  // the time of x_ (-1: none)
  bool moving_ = false;
  double unit_ = 1.0;
  // Per component, per marker: its entries on this rank (CSR).
  std::vector<std::vector<std::size_t>> start_;
  std::vector<std::vector<Entry>> entries_;
  // A stencil's points lie on one rank or on several. Each entry's place in
  // its marker's whole stencil (the support's points in z, y, x order, the
  // ones that are no unknown included); per marker and component (3 m + c)
  // that stencil's size, and for a stencil on several ranks where its terms
  // sit in interpolate's reduction (-1: on one rank).
  std::vector<std::vector<int>> slot_;
  std::vector<int> slots_;
  std::vector<long> split_at_;
  mutable std::vector<double>
      reduced_;  // interpolate's buffer: 3 sums a marker, then the split stencils' terms
  std::vector<long> touched_;
  std::array<std::vector<double>, 3> scratch_;  // zeroed copies of the grid's points (cg)
  std::vector<double> loads_;  // per body 6: force and torque times dt
  double load_time_ = 0.0;
  Result worst_;
};

}  // namespace coflow::ibm
