// fv: what the eddy viscosity does to the momentum equation (seed 003 eq.
// 3.12): div((nu + nu_t)(grad u + grad u^T)) is split into the
// variable-coefficient Laplacian div((nu + nu_t) grad u_c), implicit, and
// the rest, d/dx_d (nu_t d u_d / dx_c), explicit (with constant nu the rest
// is nu d(div u)/dx_c = 0). The isotropic part 2/3 k of the Reynolds stress is
// in the pressure (the modified pressure p* of eq. 3.11).
#include <cmath>

#include "fluid/fv/fv_solver.hpp"
#include "fluid/fv/turbulence/closure.hpp"

namespace coflow::fluid {

// div((nu + nu_t) grad u_c) at u_c's face n, from the ghosts (explicit).
double FvSolver::diffusion_at(const Field& u, int c, long n) const {
  double l = 0.0;
  for (int d = 0; d < dims_; ++d) {
    const long s = stride(d);
    l += (nu_face(c, n, d, 1) * (u[n + s] - u[n]) - nu_face(c, n, d, 0) * (u[n] - u[n - s])) / (h_[d] * h_[d]);
  }
  return l;
}

// out_c += d/dx_d (nu_t d u_d / dx_c) at u_c's faces n0 + i, i < len, along x:
// the fluxes through the control volume's sides, nu_t d u_d / dx_c at a cell
// (d = c) or an edge. Plain pointers and the dimension a template argument,
// so that the loop vectorises.
template <int DIMS, int C>
void FvSolver::stress_transpose_row(const Faces& u, long n0, long len, double* out) const {
  constexpr int c = C;
  const double* __restrict nut = nut_.data() + n0;
  const double* __restrict V[3] = {u[0].data() + n0, u[1].data() + n0, u[DIMS - 1].data() + n0};
  const long s[3] = {stride(0), stride(1), stride(2)}, sc = s[c];
  const double ih[3] = {inv_h_[0], inv_h_[1], inv_h_[2]};
  double* __restrict o = out + n0;
  for (long i = 0; i < len; ++i) {
    double r = 0.0;
#pragma GCC unroll 3
    for (int d = 0; d < DIMS; ++d) {
      const double* __restrict v = V[d];
      const long sd = s[d];
      if (d == c) {
        const double up = nut[i] * (v[i + sc] - v[i]) * ih[c];
        const double dn = nut[i - sc] * (v[i] - v[i - sc]) * ih[c];
        r += (up - dn) * ih[c];
        continue;
      }
      // An edge's four cells in one order from either side (as nu_face).
      const double nu_up = 0.25 * ((nut[i] + nut[i - sc]) + (nut[i + sd] + nut[i + sd - sc]));
      const double nu_dn = 0.25 * ((nut[i - sd] + nut[i - sd - sc]) + (nut[i] + nut[i - sc]));
      const double up = nu_up * (v[i + sd] - v[i + sd - sc]) * ih[c];
      const double dn = nu_dn * (v[i] - v[i - sc]) * ih[c];
      r += (up - dn) * ih[d];
    }
    o[i] += r;
  }
}

// out_c += d/dx_d (nu_t d u_d / dx_c) at the unknown faces (the domain faces
// are not unknowns: along x only a row's first face can be one).
void FvSolver::add_stress_transpose(const Faces& u, Faces& out) const {
  for (int c = 0; c < dims_; ++c) {
    double* o = out[static_cast<std::size_t>(c)].data();
    for_owned_rows([&](const long* at, long n0, long, long len) {
      if (c > 0 && is_boundary_face(c, at[c])) return;
      const long first = c == 0 && is_boundary_face(0, 0) ? 1 : 0;
      if (len <= first) return;
      using Row = void (FvSolver::*)(const Faces&, long, long, double*) const;
      static constexpr Row rows[2][3] = {
          {&FvSolver::stress_transpose_row<2, 0>, &FvSolver::stress_transpose_row<2, 1>, nullptr},
          {&FvSolver::stress_transpose_row<3, 0>, &FvSolver::stress_transpose_row<3, 1>,
           &FvSolver::stress_transpose_row<3, 2>}};
      (this->*rows[dims_ == 3][c])(u, n0 + first, len - first, o);
    });
  }
}

// y+ = y u_tau / nu (seed 003 eqs. 3.26-3.27) at the centres of the cells next
// to a wall, u_tau from the wall's shear (the slope at the wall of the
// parabola through the wall's velocity and the first two cells); zero in the
// other cells (a cell in a corner shows the largest of its walls': the one
// that limits the resolution; a NaN is kept). With the wall
// functions (wall: log-law) u_tau from their shear, sqrt(nu_w U / y).
std::vector<double> FvSolver::y_plus() const {
  std::vector<double> out(static_cast<std::size_t>(blk_.owned_cells()), 0.0);
  if (!turbulent_) return out;
  const fv::WallFunction wf{turb_.constants, nu_};
  for_wall_cells([&](int f, const long* at, long n) {
    const int a = f / 2;
    const long in = f % 2 == 0 ? stride(a) : -stride(a);
    const long o = at[0] + blk_.extent[0] * (at[1] + blk_.extent[1] * at[2]);
    const double y = 0.5 * h_[a];
    if (log_law_) {
      const double utau =
          std::sqrt(wf.nu_wall(y, k_[static_cast<std::size_t>(n)]) * wall_speed(f, at, n, time_) / y);
      fv::keep_largest(out[static_cast<std::size_t>(o)], y * utau / nu_);
      return;
    }
    const Face& face = faces_[static_cast<std::size_t>(f)];
    double shear2 = 0.0;
    for (int c = 0; c < dims_; ++c) {
      if (c == a) continue;
      const Field& q = u_[static_cast<std::size_t>(c)];
      const long sc = stride(c);
      const double u0 = 0.5 * (q[n] + q[n + sc]), u1 = 0.5 * (q[n + in] + q[n + in + sc]);
      const double U =
          face.velocity_at(time_)[c] * profile(f, c, at, time_);  // the wall's own velocity there
      const double slope = (9 * (u0 - U) - (u1 - U)) / (3 * h_[a]);
      shear2 += slope * slope;
    }
    const double utau = std::sqrt(nu_ * std::sqrt(shear2));
    fv::keep_largest(out[static_cast<std::size_t>(o)], 0.5 * h_[a] * utau / nu_);
  });
  return out;
}

}  // namespace coflow::fluid
