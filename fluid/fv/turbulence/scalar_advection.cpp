// fv: the advection of k and epsilon (step 1 of k_epsilon.cpp), explicit, in
// the non-divergent form -(u . grad) q = -div(u q) + q div(u) with the
// bounded upwind-biased face value (fv::face_value, van Leer's limiter), in
// sub-steps of Courant number at most 1/2. The loops run by rows along x
// with plain pointers so that they vectorise: the carried values of each
// axis's faces first (scalar_faces), then one pass for the update
// (advect_scalar_row); the sums are those of a loop per cell, in the same
// order.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "fluid/fv/fv_solver.hpp"
#include "fluid/fv/scheme.hpp"

namespace coflow::fluid {

// The sub-steps of Courant number <= 1/2 in dt, the same for k and epsilon,
// from this rank's largest |u_d| on its cells' faces (source_row finds them
// while it reads the velocity for the strain rates).
int FvSolver::scalar_substeps(double (&umax)[3], double dt) const {
  constexpr double kMaxSubsteps = 1e4;  // the step's CFL limit allows about 2 x fluid.fv.cfl
  double rate = 0.0;
  MPI_Allreduce(MPI_IN_PLACE, umax, 3, MPI_DOUBLE, MPI_MAX, comm_);
  for (int d = 0; d < dims_; ++d) rate += umax[d] * inv_h_[d];
  const double sub = std::ceil(2.0 * rate * dt * (1 - 1e-12));  // the same on every rank (reduced)
  if (!(sub <= kMaxSubsteps))  // a velocity that is not finite (infinity, or NaN: see source_row), or blew up
    throw std::runtime_error(fmt::format(
        "fv: k and epsilon would need {:.3g} advection sub-steps at t = {:.6g} s (the velocity is {}); "
        "lower fluid.fv.cfl or fluid.fv.max_step",
        sub, next_time_, std::isfinite(sub) ? "far above the step's CFL limit" : "not finite"));
  return std::max(1, static_cast<int>(sub));
}

// The carried value of q on the lower d-face of each owned cell, and on the
// upper face of the last cells along d; an inlet's own value on its face
// (`inflow`: the faces where fluid enters with a given k and epsilon).
void FvSolver::scalar_faces(const Field& q, const FaceLines& inlet, const bool (&inflow)[6], int d,
                            Field& face) const {
  const long s = stride(d), last = blk_.extent[d] - 1;
  const int lo = 2 * d;
  const double* __restrict Q = q.data();
  const double* __restrict v = u_[static_cast<std::size_t>(d)].data();
  double* __restrict F = face.data();
  auto values = [&](long m0, long len) {
    for (long m = m0; m < m0 + len; ++m)
      F[m] = fv::face_value(true, Q[m - 2 * s], Q[m - s], Q[m], Q[m + s], v[m]);
  };
  for_owned_rows([&](const long* at, long n0, long, long len) {
    values(n0, len);
    if (d == 0) values(n0 + len, 1);  // the row's last upper face
    if (d > 0 && at[d] == last) values(n0 + s, len);
    long here[3] = {0, at[1], at[2]};  // FaceLines::at reads the two coordinates across the face
    auto set = [&](int f, long n, long i) {
      here[0] = i;
      F[n] = inlet.at(f, here);
    };
    if (d == 0) {
      if (inflow[lo]) set(lo, n0, 0);
      if (inflow[lo + 1]) set(lo + 1, n0 + len, len - 1);
      return;
    }
    for (long i = 0; i < len && inflow[lo] && at[d] == 0; ++i) set(lo, n0 + i, i);
    for (long i = 0; i < len && inflow[lo + 1] && at[d] == last; ++i) set(lo + 1, n0 + i + s, i);
  });
}

// next = q + h (-(u . grad) q) at the cells n0 + i, i < len, from the faces'
// carried values.
template <int DIMS>
void FvSolver::advect_scalar_row(const double* q, const double* const (&face)[3], double h, double* next,
                                 long n0, long len) const {
  const double* __restrict Q = q + n0;
  const double* __restrict F[3] = {face[0] + n0, face[1] + n0, face[2] + n0};
  const double* __restrict V[3] = {u_[0].data() + n0, u_[1].data() + n0, u_[DIMS - 1].data() + n0};
  const long s[3] = {stride(0), stride(1), stride(2)};
  const double ih[3] = {inv_h_[0], inv_h_[1], inv_h_[2]};
  double* __restrict N = next + n0;
  for (long i = 0; i < len; ++i) {
    double rate = 0.0;
#pragma GCC unroll 3
    for (int d = 0; d < DIMS; ++d) {
      const double* __restrict v = V[d];
      const double* __restrict f = F[d];
      rate -= (v[i + s[d]] * f[i + s[d]] - v[i] * f[i] - Q[i] * (v[i + s[d]] - v[i])) * ih[d];
    }
    N[i] = Q[i] + h * rate;
  }
}

// q <- q - dt (u . grad) q in `sub` sub-steps (scalar_substeps), the ghosts
// refilled after each.
void FvSolver::advect_scalar(Field& q, const FaceLines& inlet, double wall_sign, double dt, int sub) {
  const double h = dt / sub;
  bool inflow[6];
  for (int f = 0; f < 6; ++f) {
    const Face& face = faces_[static_cast<std::size_t>(f)];
    inflow[f] = face.here && face.kind == Face::dirichlet && !face.wall;
  }
  Field& next = scratch_[5];
  Field* faces[3] = {&scratch_[4], &scratch_[6], &scratch_[7]};
  next = q;
  for (Field* f : faces) f->resize(q.size());
  const double* const face[3] = {faces[0]->data(), faces[1]->data(), faces[2]->data()};
  for (int step = 0; step < sub; ++step) {
    for (int d = 0; d < dims_; ++d) scalar_faces(q, inlet, inflow, d, *faces[d]);
    for_owned_rows([&](const long*, long n0, long, long len) {
      if (dims_ == 2)
        advect_scalar_row<2>(q.data(), face, h, next.data(), n0, len);
      else
        advect_scalar_row<3>(q.data(), face, h, next.data(), n0, len);
    });
    std::swap(q, next);
    fill_scalar_ghosts(q, inlet, wall_sign, true);
  }
}

}  // namespace coflow::fluid
