// lbm-reference: two fluids by the colour-gradient model (seed 000 §2.3.4)
// and interior solids, written out plainly (the oracle of lbm's
// two_phase_core.cpp and colour_gradient.hpp).
#include <algorithm>
#include <cmath>

#include "fluid/lbm/colour_gradient.hpp"
#include "fluid/lbm_reference/lbm_reference.hpp"

namespace coflow::fluid {

using lbm::FaceType;

void LbmReference::init_colours() {
  const long cells = n_[0] * n_[1] * n_[2];
  r_.assign(cells * Q_, 0.0);
  b_.assign(cells * Q_, 0.0);
  phi_.assign(cells, 0.0);
  solid_id_.assign(cells, 0);
  for (long k = 0; k < n_[2]; ++k)
    for (long j = 0; j < n_[1]; ++j)
      for (long i = 0; i < n_[0]; ++i) {
        const long c = index(i, j, k);
        if (s_.tp.any_solid()) solid_id_[c] = (*s_.tp.solids)[c];
        const double psi = s_.tp.on ? s_.tp.initial_phase(i, j, k) : 1.0;
        for (int q = 0; q < Q_; ++q) {
          if (solid_id_[c]) {
            f_[c * Q_ + q] = w_[q];  // at rest, reference density: what the fields show there
            continue;
          }
          r_[c * Q_ + q] = 0.5 * (1.0 + psi) * f_[c * Q_ + q];
          b_[c * Q_ + q] = 0.5 * (1.0 - psi) * f_[c * Q_ + q];
        }
      }
}

// The colour field at a cell that may be outside the box: wrapped across
// periodic faces, the walls' colour beyond the others, a solid's own colour.
LbmReference::Beyond LbmReference::beyond(long x[3]) const {
  Beyond b;
  for (int d = 0; d < 3; ++d) {
    if (x[d] >= 0 && x[d] < n_[d]) continue;
    const lbm::Face& face = s_.faces[2 * d + (x[d] < 0 ? 0 : 1)];
    if (face.type == FaceType::periodic) {
      x[d] = (x[d] + n_[d]) % n_[d];
    } else if (face.type == FaceType::wall) {
      b.wall = true;
    } else {
      b.open = &face;
      x[d] = std::clamp(x[d], 0L, n_[d] - 1);
    }
  }
  return b;
}

// Interpolated bounce-back at an interior solid (Bouzidi, Firdaouss &
// Lallemand 2001, linear; fluid.lbm.bounce_back: interpolated): population q
// of fluid cell (i, j, k), which comes from solid `id`, from the post-collision
// populations of the cell and, where the surface lies nearer than half the
// link, of the next cell away from the solid (half-way if that is not fluid);
// with fluid.lbm.bounce_back: central, the central linear interpolation of
// Ginzburg, Verhaeghe & d'Humieres (2008), f*_opp(q) + (1 - 2 delta) / (1 +
// 2 delta) (f*_opp(q) of the next cell - f*_q), from the same populations at
// every delta (half-way if the next cell is not fluid). step_colours adds what it falls short of the half-way
// value to the cell's rest population of the same colour (each colour's mass kept).
void LbmReference::bounce_interpolated(long i, long j, long k, int q, int id,
                                       const std::vector<double>& post_r, const std::vector<double>& post_b) {
  const long c = index(i, j, k);
  const int toward[3] = {-e_[q][0], -e_[q][1], -e_[q][2]};
  const double delta = s_.tp.surface->fraction({i, j, k}, toward, id);
  const long out = c * Q_ + opp_[q];
  long a[3] = {i + e_[q][0], j + e_[q][1], k + e_[q][2]};
  const Beyond at = beyond(a);
  const bool ahead_fluid = !at.wall && !at.open && !solid_id_[index(a[0], a[1], a[2])];
  if (s_.tp.central) {  // fluid.lbm.bounce_back: central (Ginzburg, Verhaeghe & d'Humieres 2008)
    if (!ahead_fluid) return;
    const long far = index(a[0], a[1], a[2]) * Q_ + opp_[q], own = c * Q_ + q;
    const double kappa = (1.0 - 2.0 * delta) / (1.0 + 2.0 * delta);
    r_[c * Q_ + q] = post_r[out] + kappa * (post_r[far] - post_r[own]);
    b_[c * Q_ + q] = post_b[out] + kappa * (post_b[far] - post_b[own]);
    return;
  }
  if (delta >= 0.5) {
    const double w = 0.5 / delta;
    r_[c * Q_ + q] = w * post_r[out] + (1.0 - w) * post_r[c * Q_ + q];
    b_[c * Q_ + q] = w * post_b[out] + (1.0 - w) * post_b[c * Q_ + q];
    return;
  }
  if (!ahead_fluid) return;
  const long far = index(a[0], a[1], a[2]) * Q_ + opp_[q];
  r_[c * Q_ + q] = 2.0 * delta * post_r[out] + (1.0 - 2.0 * delta) * post_r[far];
  b_[c * Q_ + q] = 2.0 * delta * post_b[out] + (1.0 - 2.0 * delta) * post_b[far];
}

double LbmReference::phi_at(long i, long j, long k) const {
  long x[3] = {i, j, k};
  const Beyond b = beyond(x);
  if (b.wall) return s_.tp.wall_phase;
  if (b.open && b.open->phase_given) return b.open->phase;  // else the face cell's colour
  const long c = index(x[0], x[1], x[2]);
  return solid_id_[c] ? s_.tp.solid_phase.at(solid_id_[c]) : phi_[c];
}

void LbmReference::step_colours() {
  const std::vector<double> post_r = r_, post_b = b_;
  // Streaming of each colour (eqs. 2.64-2.65) with half-way bounce-back at the
  // walls and at solid cells; the colour field of what arrived.
  for (long k = 0; k < n_[2]; ++k)
    for (long j = 0; j < n_[1]; ++j)
      for (long i = 0; i < n_[0]; ++i) {
        const long c = index(i, j, k);
        if (solid_id_[c]) continue;
        std::vector<bool> unknown(Q_, false);
        bool any = false;
        double kept_r = 0.0, kept_b = 0.0;  // what interpolated links took from each colour
        for (int q = 0; q < Q_; ++q) {
          long src[3] = {i - e_[q][0], j - e_[q][1], k - e_[q][2]};
          const Beyond at = beyond(src);
          const bool wall = at.wall, open = at.open != nullptr;
          const long s = wall || open ? -1 : index(src[0], src[1], src[2]);
          r_[c * Q_ + q] = b_[c * Q_ + q] = 0.0;  // from beyond an open face: unknown, closed below
          if (wall || (!open && solid_id_[s])) {
            r_[c * Q_ + q] = post_r[c * Q_ + opp_[q]];
            b_[c * Q_ + q] = post_b[c * Q_ + opp_[q]];
            if (!wall && s_.tp.surface) {
              bounce_interpolated(i, j, k, q, solid_id_[s], post_r, post_b);
              kept_r += post_r[c * Q_ + opp_[q]] - r_[c * Q_ + q];
              kept_b += post_b[c * Q_ + opp_[q]] - b_[c * Q_ + q];
            }
          } else if (!open) {
            r_[c * Q_ + q] = post_r[s * Q_ + q];
            b_[c * Q_ + q] = post_b[s * Q_ + q];
          }
          unknown[q] = open && !wall;
          any = any || unknown[q];
        }
        r_[c * Q_] += kept_r;  // into the rest populations: each colour's mass kept
        b_[c * Q_] += kept_b;
        if (any) close_colours(i, j, k, unknown, post_r, post_b);
        double red = 0.0, blue = 0.0;
        for (int q = 0; q < Q_; ++q) red += r_[c * Q_ + q], blue += b_[c * Q_ + q];
        phi_[c] = s_.tp.phase_field ? (red - blue) / (red + blue)
                                    : red - blue;  // the phase, or eq. 2.56's difference
      }
  // The seed's wetting: grains colour the cells they cover, by solid fraction,
  // phi <- (1 - eps) phi + eps rho cos(theta). Open faces keep their fluid.
  for (const auto& [c, grain] : solid_) {
    if (s_.tp.geometric || solid_id_[c] || on_open_face(c)) continue;
    double rho = 0.0;
    for (int q = 0; q < Q_; ++q) rho += r_[c * Q_ + q] + b_[c * Q_ + q];
    if (s_.tp.phase_field) rho = 1.0;  // the phase has no density in it
    phi_[c] = (1.0 - grain.fraction) * phi_[c] + grain.fraction * rho * grain.wetting;
  }
  if (ibm_) force_immersed([&](long c, int q) { return r_[c * Q_ + q] + b_[c * Q_ + q]; });
  step_u2_ = 0.0;
  for (long k = 0; k < n_[2]; ++k)
    for (long j = 0; j < n_[1]; ++j)
      for (long i = 0; i < n_[0]; ++i) {
        const long c = index(i, j, k);
        if (solid_id_[c]) continue;
        double g[3] = {0.0, 0.0, 0.0}, F[3];
        colour_gradient(i, j, k, g);
        total_force(c, F);
        if (ibm_) {  // the forcing's velocity scale
          std::vector<double> f(Q_);
          for (int q = 0; q < Q_; ++q) f[q] = r_[c * Q_ + q] + b_[c * Q_ + q];
          note_speed(f.data(), F);
        }
        const std::vector<double> r0(r_.begin() + c * Q_, r_.begin() + (c + 1) * Q_);
        const std::vector<double> b0(b_.begin() + c * Q_, b_.begin() + (c + 1) * Q_);
        collide_colours(c, g, F);
        const auto grain = solid_.find(c);
        if (grain != solid_.end() && !on_open_face(c)) collide_grain(c, r0, b0, F, grain->second);
      }
  if (!solid_.empty()) ++solid_steps_;
  max_u2_ = step_u2_;
  ++steps_;
}

// The populations of cell (i, j, k) that came from beyond open faces: outflow
// faces copy each colour from the next cell in (post-collision); then the
// colours' sum is closed by Zou-He or the regularized closure of each
// pressure or velocity face, in face order (apply_face's arithmetic, one
// cell). What a closure sets enters with the face's phase, or with the colour
// fraction of the cell's known populations; populations a regularized face
// rebuilds keep their colour fractions.
void LbmReference::close_colours(long i, long j, long k, std::vector<bool>& unknown,
                                 const std::vector<double>& post_r, const std::vector<double>& post_b) {
  const long c = index(i, j, k), x[3] = {i, j, k};
  double* r = &r_[c * Q_];
  double* b = &b_[c * Q_];
  const auto inner = [&](int face) {
    long in[3] = {i, j, k};
    in[face / 2] += face % 2 == 0 ? 1 : -1;
    return index(in[0], in[1], in[2]);
  };
  const auto on = [&](int face) {
    return n_[face / 2] > 1 && x[face / 2] == (face % 2 == 0 ? 0 : n_[face / 2] - 1);
  };
  for (int face = 0; face < 6; ++face) {
    if (s_.faces[face].type != FaceType::outflow || !on(face)) continue;
    const int s = face % 2 == 0 ? 1 : -1;
    for (int q = 0; q < Q_; ++q)
      if (s * e_[q][face / 2] > 0) {
        r[q] = post_r[inner(face) * Q_ + q], b[q] = post_b[inner(face) * Q_ + q];
        unknown[q] = false;
      }
  }
  double psi = -1.0, known_r = 0.0, known = 0.0;
  std::vector<double> f(Q_);
  std::vector<bool> set(Q_, false);
  bool rebuilt = false;
  for (int q = 0; q < Q_; ++q) {
    f[q] = r[q] + b[q];
    if (!unknown[q]) known_r += r[q], known += r[q] + b[q];
  }
  const double psi_known = known > 0.0 ? known_r / known : (s_.tp.on ? 0.5 : 1.0);
  if (close_corner_colours(x, r, b, f, psi_known, post_r, post_b)) return;
  for (int face = 0; face < 6; ++face) {
    const lbm::Face& F = s_.faces[face];
    if ((F.type != FaceType::pressure && F.type != FaceType::velocity) || !on(face)) continue;
    const int axis = face / 2, s = face % 2 == 0 ? 1 : -1;
    if (F.phase_given) psi = 0.5 * (1.0 + F.phase);
    double rho, u[3] = {0, 0, 0}, Fc[3];
    force_at(c, Fc);
    face_state(f.data(), axis, s, F, x, Fc, rho, u);
    if (F.regularized && F.type == FaceType::pressure) {  // with the next cell in (apply_face)
      double rho_in = 0.0, m[3] = {0, 0, 0};
      for (int q = 0; q < Q_; ++q) {
        const double g = post_r[inner(face) * Q_ + q] + post_b[inner(face) * Q_ + q];
        rho_in += g;
        for (int d = 0; d < 3; ++d) m[d] += e_[q][d] * g;
      }
      const double rho_m = s_.incompressible ? 1.0 : rho_in;
      for (int d = 0; d < 3; ++d) u[d] = 0.5 * (u[d] + (m[d] - 0.5 * Fc[d]) / rho_m);
    }
    if (F.regularized)
      regularize(f.data(), axis, s, rho, u, Fc);
    else
      zou_he(f.data(), axis, s, rho, u, Fc);
    rebuilt = rebuilt || F.regularized;
    for (int q = 0; q < Q_; ++q) set[q] = set[q] || s * e_[q][axis] > 0;
  }
  if (psi < 0.0) psi = psi_known;
  for (int q = 0; q < Q_; ++q) {
    if (!set[q] && !rebuilt) continue;
    const double red = set[q] ? psi * f[q] : lbm::share_red(f[q], r[q], b[q]);
    r[q] = red;
    b[q] = f[q] - red;
  }
}

// Where pressure or velocity faces meet: the colours' sum rebuilt whole
// (rebuild_corner; the stress with the known colour fraction's tau); what
// enters through the faces takes the first of them that gives a phase, else
// the known populations' colour fraction psi_known; the known populations
// keep their own. False where fewer than two such faces meet at x.
bool LbmReference::close_corner_colours(const long x[3], double* r, double* b, std::vector<double>& f,
                                        double psi_known, const std::vector<double>& post_r,
                                        const std::vector<double>& post_b) {
  bool meets[6];
  int meeting = 0;
  for (int face = 0; face < 6; ++face) meeting += meets[face] = open_face_at(x, face);
  if (meeting < 2) return false;
  rebuild_corner(x, f.data(), colour_tau(2.0 * psi_known - 1.0),
                 [&](long cell, int q) { return post_r[cell * Q_ + q] + post_b[cell * Q_ + q]; });
  for (int q = 0; q < Q_; ++q) {
    double psi_q = psi_known;
    for (int face = 5; face >= 0; --face)
      if (meets[face] && s_.faces[face].phase_given && (face % 2 == 0 ? 1 : -1) * e_[q][face / 2] > 0)
        psi_q = 0.5 * (1.0 + s_.faces[face].phase);
    const double red = corner_unknown(meets, q) ? psi_q * f[q] : lbm::share_red(f[q], r[q], b[q]);
    r[q] = red;
    b[q] = f[q] - red;
  }
  return true;
}

// A neighbour of a fluid cell is solid: beyond a wall face or in an interior solid.
bool LbmReference::solid_at(long i, long j, long k) const {
  long x[3] = {i, j, k};
  const Beyond b = beyond(x);
  return b.wall || (!b.open && solid_id_[index(x[0], x[1], x[2])] != 0);
}

// The colour gradient of eq. 2.56 at fluid cell (i, j, k). The seed's wetting:
// solids count with their colour cos(theta). Geometric wetting (Leclaire et al.
// 2017): next to solids, from the fluid links alone; then it turns, at
// its magnitude, to n' = -cos(theta) n_s + sin(theta) t (n_s the solids' unit
// normal into the fluid, t the gradient's unit direction along them).
void LbmReference::colour_gradient(long i, long j, long k, double g[3]) const {
  const long c = index(i, j, k);
  if (grain_gradient(i, j, k, g)) return;
  double ns[3] = {0.0, 0.0, 0.0}, cos_theta = 0.0, weight = 0.0;
  double num[3] = {0.0, 0.0, 0.0}, den[3] = {0.0, 0.0, 0.0};
  for (int q = 1; q < Q_; ++q) {
    const long a = i + e_[q][0], b = j + e_[q][1], z = k + e_[q][2];
    const bool solid = solid_at(a, b, z);
    for (int d = 0; d < 3; ++d) g[d] += e_[q][d] * phi_at(a, b, z);
    if (!solid) {
      for (int d = 0; d < 3; ++d) {
        num[d] += w_[q] * e_[q][d] * (phi_at(a, b, z) - phi_[c]);
        den[d] += w_[q] * e_[q][d] * e_[q][d];
      }
      continue;
    }
    for (int d = 0; d < 3; ++d) ns[d] -= w_[q] * e_[q][d];
    cos_theta += w_[q] * phi_at(a, b, z);
    weight += w_[q];
  }
  if (!s_.tp.geometric || weight == 0.0) return;
  // Next to solids: the gradient of the fluid links alone, per axis their
  // weighted difference over sum w e_d^2, times 2 N (N = 5 D3Q19, 3 D2Q9).
  const double N = Q_ == 19 ? 5.0 : 3.0;
  for (int d = 0; d < 3; ++d) g[d] = den[d] > 0.0 ? 2.0 * N * num[d] / den[d] : 0.0;
  turn(g, ns, cos_theta / weight);
}

// Grains' fraction at a cell that may be outside the box: 1 beyond walls and
// in solids, 0 beyond open faces.
double LbmReference::eps_at(long i, long j, long k) const {
  long x[3] = {i, j, k};
  const Beyond b = beyond(x);
  if (b.wall) return 1.0;
  if (b.open) return 0.0;
  const long c = index(x[0], x[1], x[2]);
  return solid_id_[c] ? 1.0 : grain_eps_[c];
}

// Geometric wetting next to grains (partially saturated cells), at a cell not
// wholly covered that holds or touches one: each neighbour's link weighs by
// its fluid share 1 - eps in the one-sided gradient; the solids' normal is
// -sum_q w_q e_q eps, cos(theta) their eps-weighted mean. False elsewhere.
bool LbmReference::grain_gradient(long i, long j, long k, double g[3]) const {
  const long c = index(i, j, k);
  if (!s_.tp.geometric || grain_eps_.empty() || grain_eps_[c] >= 1.0) return false;
  bool grain = grain_eps_[c] > 0.0;
  double ns[3] = {0.0, 0.0, 0.0}, cos_theta = 0.0, weight = 0.0;
  double num[3] = {0.0, 0.0, 0.0}, den[3] = {0.0, 0.0, 0.0};
  for (int q = 1; q < Q_; ++q) {
    const long a = i + e_[q][0], b = j + e_[q][1], z = k + e_[q][2];
    long x[3] = {a, b, z};
    const Beyond at = beyond(x);
    const bool solid = solid_at(a, b, z);
    const double eps = eps_at(a, b, z);
    grain = grain || (!solid && eps > 0.0);
    for (int d = 0; d < 3; ++d) ns[d] -= w_[q] * eps * e_[q][d];
    const double cos_n = solid ? phi_at(a, b, z) : at.open ? 0.0 : grain_cos_[index(x[0], x[1], x[2])];
    cos_theta += w_[q] * eps * cos_n;
    weight += w_[q] * eps;
    const double share = 1.0 - eps;
    if (share <= 0.0) continue;
    for (int d = 0; d < 3; ++d) {
      num[d] += share * w_[q] * e_[q][d] * (phi_at(a, b, z) - phi_[c]);
      den[d] += share * w_[q] * e_[q][d] * e_[q][d];
    }
  }
  if (!grain) return false;
  const double N = Q_ == 19 ? 5.0 : 3.0;
  for (int d = 0; d < 3; ++d) g[d] = den[d] > 0.0 ? 2.0 * N * num[d] / den[d] : 0.0;
  turn(g, ns, weight > 0.0 ? cos_theta / weight : 0.0);
  return true;
}

// The gradient g turned, at its magnitude, to n' = -cos(theta) n_s +
// sin(theta) t (n_s the solids' unit normal into the fluid from ns, t the
// gradient's unit direction along them); left as it is without a normal or a
// direction along the solid.
void LbmReference::turn(double g[3], double ns[3], double cos_theta) const {
  const double n = std::sqrt(ns[0] * ns[0] + ns[1] * ns[1] + ns[2] * ns[2]);
  const double gn = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  if (n == 0.0 || gn == 0.0) return;
  double t[3], along = 0.0;
  for (int d = 0; d < 3; ++d) ns[d] /= n, along += g[d] / gn * ns[d];
  for (int d = 0; d < 3; ++d) t[d] = g[d] / gn - along * ns[d];
  const double tl = std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
  if (tl < 1e-12) return;
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  for (int d = 0; d < 3; ++d) g[d] = gn * (-cos_theta * ns[d] + sin_theta * t[d] / tl);
}

// The relaxation time at colour fraction psi = (rho_r - rho_b) / rho: the
// viscosities interpolated harmonically across the interface, nu = (tau - 1/2)/3;
// psi held to [-1, 1] (a colour's density may dip below zero).
double LbmReference::colour_tau(double psi) const {
  psi = std::clamp(psi, -1.0, 1.0);
  const double nu_r = (s_.tau - 0.5) / 3.0, nu_b = ((s_.tp.on ? s_.tp.tau_blue : s_.tau) - 0.5) / 3.0;
  const double nu = 1.0 / ((1.0 + psi) / (2.0 * nu_r) + (1.0 - psi) / (2.0 * nu_b));
  return 0.5 + 3.0 * nu;
}

// A partially saturated cell in two fluids: the colour collision's result
// (in r_, b_) takes the share 1 - B; the share B is Noble & Torczynski's
// solid collision of the streamed populations (r0 + b0, eqs. 2.66-2.68), split
// between the colours by the cell's red fraction, so that each colour keeps
// its mass.
void LbmReference::collide_grain(long c, const std::vector<double>& r0, const std::vector<double>& b0,
                                 const double F[3], Solid& s) {
  std::vector<double> f0(Q_);
  double red = 0.0, blue = 0.0, rho, u[3];
  for (int q = 0; q < Q_; ++q) f0[q] = r0[q] + b0[q], red += r0[q], blue += b0[q];
  fluid_velocity(f0.data(), F, rho, u);
  const double psi = red / rho, tau = colour_tau((red - blue) / rho);
  const double B = s.fraction * (tau - 0.5) / ((1.0 - s.fraction) + (tau - 0.5));  // eq. 2.67
  for (int q = 0; q < Q_; ++q) {
    const int o = opp_[q];
    const double swap = equilibrium(q, rho, s.us) - equilibrium(o, rho, u);
    const double omega_s = f0[o] - f0[q] + swap;  // eq. 2.68
    const long x = c * Q_ + q;
    r_[x] = (1.0 - B) * r_[x] + B * (r0[o] + psi * swap);
    b_[x] = (1.0 - B) * b_[x] + B * (b0[o] + (1.0 - psi) * swap);
    f_[x] = r_[x] + b_[x];
    for (int d = 0; d < 3; ++d) s.gain[d] += B * omega_s * e_[q][d];
  }
  for (int d = 0; d < 3; ++d) s.gain[d] -= B * F[d];  // the body force's solid share (lbm/psm_kernel.hpp)
}

// Collision of r + b with the cell's relaxation time, the perturbation
// (eq. 2.57) and the recolouring (eqs. 2.59-2.63) of cell c.
void LbmReference::collide_colours(long c, const double g[3], const double F[3]) {
  double* r = &r_[c * Q_];
  double* b = &b_[c * Q_];
  double* f = &f_[c * Q_];
  double red = 0.0, blue = 0.0;
  for (int q = 0; q < Q_; ++q) {
    red += r[q];
    blue += b[q];
    f[q] = r[q] + b[q];
  }
  const double rho = red + blue, tau = colour_tau((red - blue) / rho);
  collide(f, F, tau);
  // Perturbation: 36 w A |g| [(e.g)^2/|g|^2 - C] on the moving populations,
  // C = c_s^2 / (1 - w_0) so that it keeps the mass; A = gamma / (32 N tau)
  // with N = 5 (D3Q19) or 3 (D2Q9) links per axis direction.
  const double gg = g[0] * g[0] + g[1] * g[1] + g[2] * g[2], gn = std::sqrt(gg);
  const double C = (1.0 / 3.0) / (1.0 - w_[0]), N = Q_ == 19 ? 5.0 : 3.0;
  const double A = s_.tp.gamma / (32.0 * N * tau);
  double moving_r = 0.0, moving_b = 0.0;
  for (int q = 1; q < Q_; ++q) {
    const double eg = e_[q][0] * g[0] + e_[q][1] * g[1] + e_[q][2] * g[2];
    const double len = std::sqrt(double(e_[q][0] * e_[q][0] + e_[q][1] * e_[q][1] + e_[q][2] * e_[q][2]));
    double cos_phi = 0.0;
    if (gn > 0.0) {
      f[q] += 36.0 * w_[q] * A * gn * (eg * eg / gg - C);
      cos_phi = eg / (len * gn);
    }
    r[q] = red / rho * f[q] + s_.tp.beta * red * blue / rho * w_[q] * cos_phi;
    b[q] = f[q] - r[q];
    moving_r += r[q];
    moving_b += b[q];
  }
  r[0] = red - moving_r;
  b[0] = blue - moving_b;
  for (int q = 0; q < Q_; ++q) f[q] = r[q] + b[q];
}

void LbmReference::phase_fields(std::vector<double>& phase, std::vector<double>& solid) const {
  const long cells = n_[0] * n_[1] * n_[2];
  phase.assign(cells, 1.0);
  solid.assign(cells, 0.0);
  if (!colours()) return;
  for (long c = 0; c < cells; ++c) {
    if (solid_id_[c]) {
      phase[c] = 0.0;
      solid[c] = 1.0;
      continue;
    }
    double red = 0.0, blue = 0.0;
    for (int q = 0; q < Q_; ++q) red += r_[c * Q_ + q], blue += b_[c * Q_ + q];
    phase[c] = (red - blue) / (red + blue);
  }
}

}  // namespace coflow::fluid
