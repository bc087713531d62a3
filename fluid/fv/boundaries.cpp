// fv: the ghost layers beyond the domain's faces, per face kind. The ghosts of
// a block's sides inside the domain (and periodic images) come from the ghost
// exchange; then each axis's domain faces fill their ghosts over the whole
// padded extent of the other axes, x first, so that edge and corner ghosts
// are right too.
#include <cmath>

#include "fluid/fv/fv_solver.hpp"
#include "fluid/fv/lines.hpp"

namespace coflow::fluid {

namespace {

double ramped(double value, double ramp, double t) {
  return ramp > 0 ? value * std::min(1.0, t / ramp) : value;
}

}  // namespace

Vec3 FvSolver::Face::velocity_at(double t) const {
  return {ramped(velocity[0], ramp, t), ramped(velocity[1], ramp, t), ramped(velocity[2], ramp, t)};
}
double FvSolver::Face::pressure_at(double t) const {
  return ramped(pressure, ramp, t);
}

// The velocity profile's factor at component c's place `x` (owned-relative;
// u_c sits on a c-face, the others at centres) at time t:
// BoundaryParams::profile_factor at the place's fractions of the box.
double FvSolver::profile(int face, int c, const long* x, double t) const {
  const Face& f = faces_[static_cast<std::size_t>(face)];
  if (!f.profiled) return 1.0;
  double s[3];
  for (int e = 0; e < 3; ++e)
    s[e] = (static_cast<double>(blk_.owned.lo[e] + x[e]) + (e == c ? 0.0 : 0.5)) / static_cast<double>(cells_[e]);
  return f.boundary.profile_factor(face, s, cfg_, t);
}

bool FvSolver::is_dirichlet_face(int c, long i) const {
  if (!is_boundary_face(c, i)) return false;
  return faces_[2 * c + (blk_.owned.lo[c] + i == 0 ? 0 : 1)].kind != Face::open;
}

// Component c's ghosts beyond face `side` of axis a. Wall and velocity faces
// (dirichlet): the normal component is the face's value on the face and odd
// about it; a tangential one takes the parabola through the wall's value and
// the first two cells (fv::wall_ghost). Pressure and outflow faces (open): zero normal gradient; the
// normal component on the face is the solver's (extrapolated, then projected).
// Symmetry faces: the normal component zero on the face and odd about it, the
// tangential ones even (mirrored). `top`: u is top_[c], whose value at index
// n_c - 1 along c is u_c on the upper face n_c (where a profile is taken).
void FvSolver::fill_face_ghosts(Field& u, int c, int a, int side, const Face& f, double t,
                                bool top_face) const {
  const long n = blk_.extent[a];
  const Vec3 U = f.velocity_at(t);
  const Field& top = top_[static_cast<std::size_t>(a)];
  fv::for_lines(blk_, a, [&](auto at, const long* line) {
    long place[3] = {line[0], line[1], line[2]};  // of u_c on the line's cell at index 0 along a
    if (top_face) ++place[c];
    if (f.kind == Face::symmetry && c != a) {  // mirror: no shear
      if (side == 0) {
        u[at(-1)] = u[at(0)];
        u[at(-2)] = u[at(1)];
      } else {
        u[at(n)] = u[at(n - 1)];
        u[at(n + 1)] = u[at(n - 2)];
      }
    } else if (f.kind != Face::open) {  // a wall's or velocity face's value (a symmetry face's normal: 0)
      const double v = U[c] * profile(2 * a + side, c, place, t);
      if (side == 0 && c == a) {
        u[at(0)] = v;
        u[at(-1)] = 2 * v - u[at(1)];
        u[at(-2)] = 2 * v - u[at(2)];
      } else if (log_law_ && f.wall && c != a) {  // the wall functions' line through the wall's value
        u[at(side == 0 ? -1 : n)] = 2 * v - u[at(side == 0 ? 0 : n - 1)];
        u[at(side == 0 ? -2 : n + 1)] = 2 * v - u[at(side == 0 ? 1 : n - 2)];
      } else if (side == 0) {
        u[at(-1)] = fv::wall_ghost(v, u[at(0)], u[at(1)]);
        u[at(-2)] = fv::wall_ghost2(v, u[at(0)], u[at(1)]);
      } else if (c == a) {
        u[at(n)] = v;
        u[at(n + 1)] = 2 * v - u[at(n - 1)];
      } else {
        u[at(n)] = fv::wall_ghost(v, u[at(n - 1)], u[at(n - 2)]);
        u[at(n + 1)] = fv::wall_ghost2(v, u[at(n - 1)], u[at(n - 2)]);
      }
    } else if (side == 0) {
      u[at(-1)] = u[at(-2)] = u[at(0)];
    } else if (c == a) {
      u[at(n)] = top[at(n - 1)];
      u[at(n + 1)] = u[at(n)];
    } else {
      u[at(n)] = u[at(n + 1)] = u[at(n - 1)];
    }
  });
}

void FvSolver::fill_ghosts(Faces& u, double t) {
  for (int c = 0; c < dims_; ++c) {
    ex_.exchange(u[static_cast<std::size_t>(c)]);
    if (faces_[static_cast<std::size_t>(2 * c + 1)].kind == Face::open)
      ex_.exchange(top_[static_cast<std::size_t>(c)]);
  }
  for (int a = 0; a < dims_; ++a)
    for (int side = 0; side < 2; ++side) {
      const Face& f = faces_[static_cast<std::size_t>(2 * a + side)];
      if (!f.here || f.kind == Face::periodic) continue;
      for (int c = 0; c < dims_; ++c) fill_face_ghosts(u[static_cast<std::size_t>(c)], c, a, side, f, t);
      // The upper open faces of the later axes keep their normal velocity in
      // top_; its ghosts beyond this face follow the same rule, so that the
      // corner ghosts beyond both (u_c at face n_c, which the later axis's
      // fill takes from top_) come from this step's values, as fv-reference's.
      for (int c = a + 1; c < dims_; ++c)
        if (faces_[static_cast<std::size_t>(2 * c + 1)].kind == Face::open)
          fill_face_ghosts(top_[static_cast<std::size_t>(c)], c, a, side, f, t, true);
    }
}

// Pressure (or its increment from t0 to t): the face's value on an open face
// (a ghost at 2 p_b - p), zero normal gradient at the others.
void FvSolver::fill_pressure_ghosts(Field& p, double t, bool increment, double t0) {
  ex_.exchange(p);
  for (int a = 0; a < dims_; ++a)
    for (int side = 0; side < 2; ++side) {
      const Face& f = faces_[static_cast<std::size_t>(2 * a + side)];
      if (!f.here || f.kind == Face::periodic) continue;
      const double pb =
          f.kind == Face::open ? (increment ? f.pressure_at(t) - f.pressure_at(t0) : f.pressure_at(t)) : 0;
      const double odd = f.kind == Face::open ? -1.0 : 1.0, base = f.kind == Face::open ? 2 * pb : 0.0;
      const long n = blk_.extent[a];
      fv::for_lines(blk_, a, [&](auto at, const long*) {
        for (long g = 1; g <= 2; ++g) {
          const long ghost = side == 0 ? -g : n - 1 + g, mirror = side == 0 ? g - 1 : n - g;
          p[at(ghost)] = base + odd * p[at(mirror)];
        }
      });
    }
}

// The normal velocity through an open face before the projection: that of the
// first face inside (zero gradient) at a pressure face; at an outflow face the
// convective condition du/dt + U du/dn = 0 (Orlanski 1976's radiation
// condition with the phase speed U set to the face's mean outward velocity),
// upwind from the first face inside. The upper face's
// value goes to top_.
void FvSolver::extrapolate_open_faces(Faces& u, double dt) {
  for (int a = 0; a < dims_; ++a) {
    const auto A = static_cast<std::size_t>(a);
    const long n = blk_.extent[a];
    const double k = dt / h_[a];
    for (int side = 0; side < 2; ++side) {
      const Face& f = faces_[2 * A + static_cast<std::size_t>(side)];
      if (f.kind != Face::open) continue;
      const double U = f.convective ? outflow_speed(2 * a + side) : 0.0;  // collective
      if (!f.here) continue;
      if (side == 0 && !f.convective)
        fv::for_lines(blk_, a, [&](auto at, const long*) { u[A][at(0)] = u[A][at(1)]; });
      else if (side == 0)
        fv::for_lines(blk_, a, [&](auto at, const long*) {
          u[A][at(0)] = u_[A][at(0)] - k * U * (u_[A][at(0)] - u_[A][at(1)]);
        });
      else if (!f.convective)
        fv::for_lines(blk_, a, [&](auto at, const long*) { top_[A][at(n - 1)] = u[A][at(n - 1)]; });
      else
        fv::for_lines(blk_, a, [&](auto at, const long*) {
          top_[A][at(n - 1)] -= k * U * (top_[A][at(n - 1)] - u_[A][at(n - 1)]);
        });
    }
  }
}

// The mean outward normal velocity of the last step on an outflow face (0 if
// the mean flows in); collective.
double FvSolver::outflow_speed(int face) const {
  const int a = face / 2, side = face % 2;
  const auto A = static_cast<std::size_t>(a);
  double sum = 0.0;
  if (faces_[static_cast<std::size_t>(face)].here)
    for_owned([&](const long* at, long n, long) {
      if (side == 0 && at[a] == 0) sum -= u_[A][static_cast<std::size_t>(n)];
      if (side == 1 && at[a] == blk_.extent[a] - 1) sum += top_[A][static_cast<std::size_t>(n)];
    });
  MPI_Allreduce(MPI_IN_PLACE, &sum, 1, MPI_DOUBLE, MPI_SUM, comm_);
  const double area = static_cast<double>(cells_[0] * cells_[1] * cells_[2] / cells_[a]);
  return std::max(0.0, sum / area);
}

}  // namespace coflow::fluid
