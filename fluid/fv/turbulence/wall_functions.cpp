// fv: the wall functions of `wall: log-law` (fv::WallFunction, Launder &
// Spalding 1974; not the seed's two-layer model). In the cells next to a wall
// (their centres y = h/2 from it):
//   - the wall's shear: the tangential velocity's ghost beyond the wall is
//     the line through the wall's value (boundaries.cpp), and nu_t beyond
//     the wall is set so that the wall face's viscosity (nu_face) is the
//     wall function's nu_w: the flux nu_w (u0 - U) / (h/2) is tau_w;
//   - the production of k: tau_w dU/dy of the log law, in place of nu_t S^2;
//   - epsilon: the log law's equilibrium value, held fixed in its solve;
//   - k: no flux through the wall.
// A cell beside two walls (a corner) adds both walls' production and takes
// the larger epsilon.
#include <algorithm>
#include <cmath>

#include "fluid/fv/fv_solver.hpp"
#include "fluid/fv/lines.hpp"
#include "fluid/fv/turbulence/closure.hpp"

namespace coflow::fluid {

// The speed of the fluid at cell n's centre relative to wall `f` (its
// velocity at time t, a profile's factor read where u_c's lower face meets
// the wall, as y_plus reads it), along the wall (the mean of each tangential
// component's two faces).
double FvSolver::wall_speed(int f, const long* at, long n, double t) const {
  const Face& w = faces_[static_cast<std::size_t>(f)];
  double s2 = 0.0;
  for (int c = 0; c < dims_; ++c) {
    if (c == f / 2) continue;
    const Field& q = u_[static_cast<std::size_t>(c)];
    const double U = w.velocity_at(t)[c] * profile(f, c, at, t);
    const double u = 0.5 * (q[n] + q[n + stride(c)]) - U;
    s2 += u * u;
  }
  return std::sqrt(s2);
}

// nu_t beyond each wall: 2 (nu_w - nu) - nu_t of the cell beside, so that
// the mean over the wall face is nu_w - nu (nu_face adds nu). On every padded
// line (the block's ghost lines too, where nu_face reads them).
void FvSolver::wall_function_ghosts() {
  const fv::WallFunction wf{turb_.constants, nu_};
  for (int f = 0; f < 2 * dims_; ++f) {
    const Face& w = faces_[static_cast<std::size_t>(f)];
    if (!w.here || !w.wall) continue;
    const int a = f / 2;
    const long n = blk_.extent[a];
    const double y = 0.5 * h_[a];
    fv::for_lines(blk_, a, [&](auto at, const long*) {
      const std::size_t in = at(f % 2 == 0 ? 0 : n - 1);
      const double g = 2.0 * (wf.nu_wall(y, std::max(k_[in], 0.0)) - nu_) - nut_[in];
      nut_[at(f % 2 == 0 ? -1 : n)] = g;
      nut_[at(f % 2 == 0 ? -2 : n + 1)] = g;
    });
  }
}

// The production of k in the cells next to a wall: the sum over their walls
// of tau_w dU/dy (WallFunction::production), replacing nu_t S^2.
void FvSolver::wall_function_production(Field& production) const {
  const fv::WallFunction wf{turb_.constants, nu_};
  for_wall_cells([&](int, const long*, long n) { production[static_cast<std::size_t>(n)] = 0.0; });
  for_wall_cells([&](int f, const long* at, long n) {
    const auto N = static_cast<std::size_t>(n);
    production[N] += wf.production(0.5 * h_[f / 2], k_[N], wall_speed(f, at, n, next_time_));
  });
}

// epsilon of the cells next to a wall (the larger over their walls), marked
// fixed (1) for the epsilon solve, every other cell 0. On every padded line:
// a fixed cell in the halo (a neighbour's wall cell, or a periodic image)
// must be fixed on this side too, so that the rows beside it take it to the
// right-hand side and the matrix stays symmetric (k there is exchanged).
void FvSolver::wall_function_epsilon(Field& fixed) {
  const fv::WallFunction wf{turb_.constants, nu_};
  fixed.assign(k_.size(), 0.0);
  for (int f = 0; f < 2 * dims_; ++f) {
    const Face& w = faces_[static_cast<std::size_t>(f)];
    if (!w.here || !w.wall) continue;
    const long n = blk_.extent[f / 2];
    const double y = 0.5 * h_[f / 2];
    fv::for_lines(blk_, f / 2, [&](auto at, const long*) {
      const std::size_t c = at(f % 2 == 0 ? 0 : n - 1);
      const double e = wf.epsilon(y, std::max(k_[c], 0.0));
      eps_[c] = fixed[c] > 0 ? std::max(eps_[c], e) : e;
      fixed[c] = 1.0;
    });
  }
}

}  // namespace coflow::fluid
