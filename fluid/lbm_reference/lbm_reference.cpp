#include "fluid/lbm_reference/lbm_reference.hpp"

#include <fmt/format.h>

#include <cmath>
#include <functional>
#include <stdexcept>

#include "coflow/log.hpp"
#include "coflow/session.hpp"
#include "fluid/grid/cell_fields.hpp"
#include "fluid/lbm/phase_series.hpp"

namespace coflow::fluid {

using lbm::FaceType;

LbmReference::LbmReference(const Setup& setup, const Params& p)
    : s_(lbm::make_setup(setup.cfg, setup.params, p, setup.time_step)), cfg_(&setup.cfg), comm_(setup.comm) {
  int size = 1;
  MPI_Comm_size(comm_, &size);
  if (size != 1) throw std::runtime_error("lbm-reference is serial: set fluid.ranks: 1");
  box_ = setup.decomposition.block(0);
  for (int d = 0; d < 3; ++d) n_[d] = s_.cells[d];
  auto load = [&](const auto& L) {
    using Lat = std::decay_t<decltype(L)>;
    Q_ = Lat::Q;
    for (int q = 0; q < Lat::Q; ++q) {
      e_.push_back({Lat::e[q][0], Lat::e[q][1], Lat::e[q][2]});
      w_.push_back(Lat::w[q]);
      opp_.push_back(Lat::opp[q]);
    }
  };
  if (s_.d3)
    load(lbm::D3Q19{});
  else
    load(lbm::D2Q9{});
  const long cells = n_[0] * n_[1] * n_[2];
  f_.resize(cells * Q_);
  for (long k = 0; k < n_[2]; ++k)
    for (long j = 0; j < n_[1]; ++j)
      for (long i = 0; i < n_[0]; ++i) {
        double rho, u[3];
        s_.initial(i, j, k, rho, u);
        // Stored f is post-collision, its momentum rho u + F/2 (Guo): the body
        // force's half, 3 w e.F / 2, is added so that u is the one given.
        for (int q = 0; q < Q_; ++q) {
          const double eF = e_[q][0] * s_.force[0] + e_[q][1] * s_.force[1] + e_[q][2] * s_.force[2];
          f_[index(i, j, k) * Q_ + q] = equilibrium(q, rho, u) + 1.5 * w_[q] * eF;
        }
      }
  if (colours()) init_colours();
  log::info("lbm-reference {} {}: {}", s_.d3 ? "D3Q19" : "D2Q9",
            s_.incompressible ? "incompressible" : "standard", s_.units.describe());
}

// Equilibrium, seed 000 eq. 2.33 (standard) and eq. 2.47 divided by c_s^2
// (incompressible, with p_0 = c_s^2 rho_0 and rho_0 = 1).
double LbmReference::equilibrium(int q, double rho, const double u[3]) const {
  const double eu = e_[q][0] * u[0] + e_[q][1] * u[1] + e_[q][2] * u[2];
  const double uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
  const double rho_m = s_.incompressible ? 1.0 : rho;
  return w_[q] * (rho + rho_m * (3.0 * eu + 4.5 * eu * eu - 1.5 * uu));
}

// Collision with Guo, Zheng & Shi (2002) forcing, written per population pair
// (q, opposite q): the even part relaxes with tau (seed 000 eqs 2.42, 2.45, BGK),
// the odd part with tau_minus (TRT, Ginzburg 2008; tau_minus = tau for BGK).
void LbmReference::set_source(std::span<const double> force_density) {
  source_.resize(force_density.size());
  for (std::size_t n = 0; n < source_.size(); ++n) source_[n] = force_density[n] / s_.units.force_density();
}

// The force density acting on cell c: the uniform body force plus the cell's
// momentum source (immersed method point), lattice units.
void LbmReference::force_at(long c, double F[3]) const {
  for (int d = 0; d < 3; ++d) F[d] = s_.force[d] + (source_.empty() ? 0.0 : source_[3 * c + d]);
}

void LbmReference::fluid_velocity(const double* f, const double* F, double& rho, double u[3]) const {
  double j[3] = {0, 0, 0};
  rho = 0.0;
  for (int q = 0; q < Q_; ++q) {
    rho += f[q];
    for (int d = 0; d < 3; ++d) j[d] += e_[q][d] * f[q];
  }
  const double rho_m = s_.incompressible ? 1.0 : rho;
  for (int d = 0; d < 3; ++d) u[d] = (j[d] + 0.5 * F[d]) / rho_m;
}

void LbmReference::collide(double* f, const double* F, double tau) const {
  double rho, u[3];
  fluid_velocity(f, F, rho, u);
  const double rho_m = s_.incompressible ? 1.0 : rho;
  const double tau_minus = s_.trt ? 0.5 + s_.magic / (tau - 0.5) : tau;
  const double uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
  const double uF = u[0] * F[0] + u[1] * F[1] + u[2] * F[2];
  double moving = 0.0;
  for (int q = 1; q < Q_; ++q) {
    const int o = opp_[q];
    if (o < q) continue;
    const double eu = e_[q][0] * u[0] + e_[q][1] * u[1] + e_[q][2] * u[2];
    const double eF = e_[q][0] * F[0] + e_[q][1] * F[1] + e_[q][2] * F[2];
    // Even and odd parts of the pair and of its equilibrium (eq. 2.33 / 2.47).
    const double plus = 0.5 * (f[q] + f[o]), minus = 0.5 * (f[q] - f[o]);
    const double eq_plus = w_[q] * (rho + rho_m * (4.5 * eu * eu - 1.5 * uu));
    const double eq_minus = w_[q] * rho_m * 3.0 * eu;
    const double source_plus = (1.0 - 0.5 / tau) * w_[q] * (9.0 * eu * eF - 3.0 * uF);
    const double source_minus = (1.0 - 0.5 / tau_minus) * w_[q] * 3.0 * eF;
    const double even = (plus - eq_plus) / tau - source_plus;
    const double odd = (minus - eq_minus) / tau_minus - source_minus;
    f[q] = f[q] - even - odd;
    f[o] = f[o] - even + odd;
    moving += f[q] + f[o];
  }
  // The rest population takes the mass the others leave (no rounding bias).
  f[0] = rho - moving;
}

void LbmReference::collide_psm(double* f, const double* F, Solid& s) const {
  double rho, u[3];
  fluid_velocity(f, F, rho, u);
  const double tau = s_.tau;
  const double tau_minus = s_.trt ? 0.5 + s_.magic / (tau - 0.5) : tau;  // TRT: odd parts (collide())
  const double B = s.fraction * (tau - 0.5) / ((1.0 - s.fraction) + (tau - 0.5));  // eq. 2.67
  std::vector<double> feq(Q_), feq_s(Q_), out(Q_);
  for (int q = 0; q < Q_; ++q) {
    feq[q] = equilibrium(q, rho, u);
    feq_s[q] = equilibrium(q, rho, s.us);
  }
  for (int q = 0; q < Q_; ++q) {
    const int o = opp_[q];
    const double omega_s = f[o] - feq[o] + feq_s[q] - f[q];  // eq. 2.68 (Noble & Torczynski's form)
    double eu = 0, eF = 0, uF = 0;
    for (int d = 0; d < 3; ++d) {
      eu += e_[q][d] * u[d];
      eF += e_[q][d] * F[d];
      uF += u[d] * F[d];
    }
    if (!s_.trt) {  // BGK
      const double omega = 1.0 / tau;
      const double S = (1.0 - 0.5 * omega) * w_[q] * (3.0 * (eF - uF) + 9.0 * eu * eF);
      out[q] = f[q] - (1.0 - B) * omega * (f[q] - feq[q]) + (1.0 - B) * S + B * omega_s;  // eq. 2.66
    } else {  // TRT: the fluid's even and odd parts apart, as collide() has them
      const double even = 0.5 * (f[q] + f[o]) - 0.5 * (feq[q] + feq[o]);
      const double odd = 0.5 * (f[q] - f[o]) - 0.5 * (feq[q] - feq[o]);
      const double S =
          (1.0 - 0.5 / tau) * w_[q] * (9.0 * eu * eF - 3.0 * uF) + (1.0 - 0.5 / tau_minus) * w_[q] * 3.0 * eF;
      out[q] = f[q] + (1.0 - B) * (-even / tau - odd / tau_minus + S) + B * omega_s;  // eq. 2.66
    }
    for (int d = 0; d < 3; ++d) s.gain[d] += B * omega_s * e_[q][d];
  }
  // The solid takes the body force's share B, which the fluid's source leaves
  // (fluid/lbm/psm_kernel.hpp).
  for (int d = 0; d < 3; ++d) s.gain[d] -= B * F[d];
  for (int q = 0; q < Q_; ++q) f[q] = out[q];
}

bool LbmReference::on_open_face(long c) const {
  const long x[3] = {c % n_[0], (c / n_[0]) % n_[1], c / (n_[0] * n_[1])};
  for (int f = 0; f < 6; ++f) {
    const FaceType t = s_.faces[f].type;
    const bool open = t == FaceType::pressure || t == FaceType::velocity || t == FaceType::outflow;
    if (open && n_[f / 2] > 1 && x[f / 2] == (f % 2 == 0 ? 0 : n_[f / 2] - 1)) return true;
  }
  return false;
}

void LbmReference::set_solid(std::span<const long> cells, std::span<const double> fraction,
                             std::span<const double> velocity, std::span<const double> wetting) {
  solid_.clear();
  solid_order_.assign(cells.begin(), cells.end());
  if (colours()) {  // the grains' cells for geometric wetting: not in solids, not on open faces
    grain_eps_.assign(static_cast<std::size_t>(n_[0] * n_[1] * n_[2]), 0.0);
    grain_cos_.assign(grain_eps_.size(), 0.0);
    for (std::size_t n = 0; n < cells.size(); ++n)
      if (!solid_id_[cells[n]] && !on_open_face(cells[n]))
        grain_eps_[cells[n]] = fraction[n], grain_cos_[cells[n]] = wetting[n];
  }
  for (std::size_t n = 0; n < cells.size(); ++n) {
    Solid& s = solid_[cells[n]];
    s.fraction = fraction[n];
    s.wetting = wetting[n];
    for (int d = 0; d < 3; ++d) s.us[d] = velocity[3 * n + d] / s_.units.velocity();
  }
  solid_steps_ = 0;
}

void LbmReference::take_solid_force(std::vector<double>& force) {
  // Minus the fluid's momentum gain per step, in newtons (eqs 2.69-2.70).
  const auto& u = s_.units;
  const double unit = u.rho * u.dx * u.dx * u.dx * u.velocity() / u.dt;
  force.assign(3 * solid_order_.size(), 0.0);
  for (std::size_t n = 0; n < solid_order_.size(); ++n) {
    Solid& s = solid_.at(solid_order_[n]);
    for (int d = 0; d < 3; ++d) {
      if (solid_steps_ > 0) force[3 * n + d] = -s.gain[d] * unit / solid_steps_;
      s.gain[d] = 0.0;
    }
  }
  solid_steps_ = 0;
}

void LbmReference::step() {
  if (colours()) {
    step_colours();
    return;
  }
  const std::vector<double> post = f_;
  std::vector<double> fs(f_.size(), 0.0);
  // Streaming (seed 000 eq. 2.43): pull from the upwind neighbour. A population
  // that would come through a wall is the one that left towards it, reversed
  // (half-way bounce-back, eq. 2.44); through a periodic face it wraps; through a
  // pressure, velocity or outflow face it is unknown and set by the face below.
  for (long k = 0; k < n_[2]; ++k)
    for (long j = 0; j < n_[1]; ++j)
      for (long i = 0; i < n_[0]; ++i) {
        const long x[3] = {i, j, k};
        for (int q = 0; q < Q_; ++q) {
          long src[3];
          bool wall = false, open = false;
          for (int d = 0; d < 3; ++d) {
            src[d] = x[d] - e_[q][d];
            if (src[d] >= 0 && src[d] < n_[d]) continue;
            const lbm::Face& face = s_.faces[2 * d + (src[d] < 0 ? 0 : 1)];
            if (face.type == FaceType::periodic)
              src[d] = (src[d] + n_[d]) % n_[d];
            else if (face.type == FaceType::wall)
              wall = true;
            else
              open = true;
          }
          const long c = index(i, j, k);
          if (wall)
            fs[c * Q_ + q] = post[c * Q_ + opp_[q]];
          else if (!open)
            fs[c * Q_ + q] = post[index(src[0], src[1], src[2]) * Q_ + q];
        }
      }
  // Outflow faces first: their closure uses no unknowns of other faces, so a
  // Zou-He node on a shared edge sees only defined populations.
  for (int face = 0; face < 6; ++face)
    if (s_.faces[face].type == FaceType::outflow) apply_face(face, fs, post);
  for (int face = 0; face < 6; ++face)
    if (s_.faces[face].type != FaceType::outflow) apply_face(face, fs, post);
  close_corners(fs, post);
  if (ibm_) force_immersed([&](long c, int q) { return fs[c * Q_ + q]; });
  step_u2_ = 0.0;
  for (long c = 0; c < n_[0] * n_[1] * n_[2]; ++c) {
    const auto it = solid_.find(c);
    double F[3];
    total_force(c, F);
    if (ibm_) note_speed(&fs[c * Q_], F);  // the forcing's velocity scale
    if (it == solid_.end() || on_open_face(c))  // open faces keep their closure: fluid
      collide(&fs[c * Q_], F, s_.tau);
    else
      collide_psm(&fs[c * Q_], F, it->second);
  }
  if (!solid_.empty()) ++solid_steps_;
  f_ = fs;
  max_u2_ = step_u2_;
  ++steps_;
}

// Zou & He (1997) pressure and velocity faces, in the general form of Hecht &
// Harting (2010) for D3Q19; outflow copies the unknowns from the next node in.
void LbmReference::apply_face(int face, std::vector<double>& fs, const std::vector<double>& post) {
  const lbm::Face& F = s_.faces[face];
  if (F.type == FaceType::periodic || F.type == FaceType::wall) return;
  const int axis = face / 2;
  const int s = face % 2 == 0 ? 1 : -1;  // inward normal
  const long layer = face % 2 == 0 ? 0 : n_[axis] - 1;
  long lo[3] = {0, 0, 0}, hi[3] = {n_[0], n_[1], n_[2]};
  lo[axis] = layer;
  hi[axis] = layer + 1;
  for (long k = lo[2]; k < hi[2]; ++k)
    for (long j = lo[1]; j < hi[1]; ++j)
      for (long i = lo[0]; i < hi[0]; ++i) {
        double* f = &fs[index(i, j, k) * Q_];
        const long at_node[3] = {i, j, k};
        if (F.type != FaceType::outflow && meeting_faces(at_node) > 1) continue;  // close_corners
        if (F.type == FaceType::outflow) {
          // Zero gradient: the unknowns are the next node's populations of the
          // previous step (post-collision), which depend on no other face.
          long in[3] = {i, j, k};
          in[axis] += s;
          const double* g = &post[index(in[0], in[1], in[2]) * Q_];
          for (int q = 0; q < Q_; ++q)
            if (s * e_[q][axis] > 0) f[q] = g[q];
          continue;
        }
        double rho, u[3] = {0, 0, 0}, Fc[3];
        force_at(index(i, j, k), Fc);
        const long at[3] = {i, j, k};
        face_state(f, axis, s, F, at, Fc, rho, u);
        if (F.regularized && F.type == FaceType::pressure) {
          // The mean of the mass-balance velocity and that of the next node
          // in, from its post-collision populations of the last step (momentum
          // rho u + F/2 with Guo's forcing; the node's own force stands for
          // the inner node's): no odd-even mode at the face (lbm/boundaries.hpp).
          long in[3] = {i, j, k};
          in[axis] += s;
          const double* g = &post[index(in[0], in[1], in[2]) * Q_];
          double rho_in = 0.0, m[3] = {0, 0, 0};
          for (int q = 0; q < Q_; ++q) {
            rho_in += g[q];
            for (int d = 0; d < 3; ++d) m[d] += e_[q][d] * g[q];
          }
          const double rho_m = s_.incompressible ? 1.0 : rho_in;
          for (int d = 0; d < 3; ++d) u[d] = 0.5 * (u[d] + (m[d] - 0.5 * Fc[d]) / rho_m);
        }
        if (F.regularized)
          regularize(f, axis, s, rho, u, Fc);
        else
          zou_he(f, axis, s, rho, u, Fc);
      }
}

// Where two or three pressure or velocity faces meet (an edge or a corner
// of the box), apply_face leaves the node alone: each face's unknowns
// include populations only the other face could set. The node is rebuilt
// whole here (lbm/boundaries.hpp, close_corner): f = f^eq(rho, u) + w / (2
// c_s^4) Q : Pi; u the first velocity face's value, else the next node's
// inwards along the diagonal; rho the first pressure face's, else that
// node's; Pi between the faces' normal axes -rho_m c_s^2 tau (du_b/dx_a +
// du_a/dx_b) (Skordos 1993), one-sided from the next node inwards along
// each normal, and along the other axes the known populations'
// non-equilibrium parts (an unknown one's from its opposite).
void LbmReference::close_corners(std::vector<double>& fs, const std::vector<double>& post) const {
  for (long k = 0; k < n_[2]; ++k)
    for (long j = 0; j < n_[1]; ++j)
      for (long i = 0; i < n_[0]; ++i) {
        const long x[3] = {i, j, k};
        if (meeting_faces(x) >= 2)
          rebuild_corner(x, &fs[index(i, j, k) * Q_], s_.tau,
                         [&](long c, int q) { return post[c * Q_ + q]; });
      }
}

// The corner node x's populations f (full; the known ones as pulled) rebuilt
// whole (close_corners), tau in the stress; post(c, q): the last step's
// population q of cell c.
void LbmReference::rebuild_corner(const long x[3], double* f, double tau,
                                  const std::function<double(long, int)>& post) const {
  double F[3];
  force_at(index(x[0], x[1], x[2]), F);
  // The density and velocity of cell c from its last step's (post-collision) populations.
  const auto state = [&](const long c[3], double u[3]) {
    const long at = index(c[0], c[1], c[2]);
    double rho = 0.0, m[3] = {0, 0, 0};
    for (int q = 0; q < Q_; ++q) {
      rho += post(at, q);
      for (int d = 0; d < 3; ++d) m[d] += e_[q][d] * post(at, q);
    }
    for (int d = 0; d < 3; ++d) u[d] = (m[d] - 0.5 * F[d]) / (s_.incompressible ? 1.0 : rho);
    return rho;
  };
  bool meets[6], normal[3] = {false, false, false};
  long in[3] = {x[0], x[1], x[2]};
  for (int face = 0; face < 6; ++face) {
    meets[face] = open_face_at(x, face);
    if (meets[face]) normal[face / 2] = true, in[face / 2] += face % 2 == 0 ? 1 : -1;
  }
  double u[3];
  double rho = state(in, u);
  for (int face = 5; face >= 0; --face)  // the first in face order wins
    if (meets[face] && s_.faces[face].type == FaceType::velocity) s_.faces[face].velocity(x, face / 2, u);
  for (int face = 5; face >= 0; --face)
    if (meets[face] && s_.faces[face].type == FaceType::pressure) rho = s_.faces[face].rho;
  std::vector<double> feq(Q_);
  for (int q = 0; q < Q_; ++q)
    feq[q] = equilibrium(q, rho, u) - 1.5 * w_[q] * (e_[q][0] * F[0] + e_[q][1] * F[1] + e_[q][2] * F[2]);
  double pi[3][3] = {};
  for (int q = 0; q < Q_; ++q) {
    const int src = corner_unknown(meets, q) ? opp_[q] : q;
    const double neq = corner_unknown(meets, src) ? 0.0 : f[src] - feq[src];
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) pi[a][b] += e_[q][a] * e_[q][b] * neq;
  }
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      if (!normal[a] || !normal[b]) continue;
      // d u_b / d x_a and d u_a / d x_b, one-sided into the box
      double ua[3], ub[3];
      long na[3] = {x[0], x[1], x[2]}, nb[3] = {x[0], x[1], x[2]};
      na[a] = in[a], nb[b] = in[b];
      state(na, ua), state(nb, ub);
      const double dab = (ua[b] - u[b]) * (in[a] - x[a]), dba = (ub[a] - u[a]) * (in[b] - x[b]);
      pi[a][b] = -(s_.incompressible ? 1.0 : rho) * tau / 3.0 * (dab + dba);
    }
  for (int q = 0; q < Q_; ++q) {
    double qpi = 0.0;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) qpi += (e_[q][a] * e_[q][b] - (a == b ? 1.0 / 3.0 : 0.0)) * pi[a][b];
    f[q] = feq[q] + 4.5 * w_[q] * qpi;
  }
}

// Whether population q enters a corner node through one of the faces that meet there.
bool LbmReference::corner_unknown(const bool meets[6], int q) const {
  for (int face = 0; face < 6; ++face)
    if (meets[face] && (face % 2 == 0 ? 1 : -1) * e_[q][face / 2] > 0) return true;
  return false;
}

// Whether face is a pressure or velocity face of the box at cell x.
bool LbmReference::open_face_at(const long x[3], int face) const {
  const int a = face / 2;
  const FaceType t = s_.faces[face].type;
  return n_[a] > 1 && (t == FaceType::pressure || t == FaceType::velocity) &&
         x[a] == (face % 2 == 0 ? 0 : n_[a] - 1);
}

// How many pressure or velocity faces of the box meet at cell x.
int LbmReference::meeting_faces(const long x[3]) const {
  int n = 0;
  for (int face = 0; face < 6; ++face) n += open_face_at(x, face);
  return n;
}

// rho and u of a face node from its known populations and the face's value
// (Zou & He 1997): a velocity face gives u, a pressure face rho. The
// populations hold the momentum rho_m u - Fc/2 (Guo's forcing, Fc the node's
// force density): the mass balance takes its normal part.
void LbmReference::face_state(const double* f, int axis, int s, const lbm::Face& F, const long at[3],
                              const double Fc[3], double& rho, double u[3]) const {
  double s0 = 0, sout = 0;
  for (int q = 0; q < Q_; ++q) {
    if (e_[q][axis] == 0) s0 += f[q];
    if (s * e_[q][axis] < 0) sout += f[q];
  }
  const double known = s0 + 2 * sout - 0.5 * s * Fc[axis];
  if (F.type == FaceType::velocity) {
    F.velocity(at, axis, u);  // the face's value times its profile's factor at this node
    const double un = s * u[axis];
    rho = s_.incompressible ? known + un : known / (1.0 - un);
  } else {
    rho = F.rho;
    const double un = s_.incompressible ? rho - known : 1.0 - known / rho;
    u[axis] = s * un;
  }
}

// The unknown populations by Zou & He (1997) in Hecht & Harting's (2010)
// form, for the momentum the populations hold, j = rho_m u - Fc/2.
void LbmReference::zou_he(double* f, int axis, int s, double rho, const double u[3],
                          const double Fc[3]) const {
  const double rho_m = s_.incompressible ? 1.0 : rho;
  double j[3];
  for (int d = 0; d < 3; ++d) j[d] = rho_m * u[d] - 0.5 * Fc[d];
  double N[3] = {0, 0, 0};
  for (int t = 0; t < 3; ++t) {
    if (t == axis) continue;
    for (int q = 0; q < Q_; ++q)
      if (e_[q][axis] == 0) N[t] += 0.5 * f[q] * e_[q][t];
    N[t] -= j[t] / 3.0;
  }
  for (int q = 0; q < Q_; ++q) {
    if (s * e_[q][axis] <= 0) continue;
    const double ej = e_[q][0] * j[0] + e_[q][1] * j[1] + e_[q][2] * j[2];
    double v = f[opp_[q]] + 6.0 * w_[q] * ej;
    for (int t = 0; t < 3; ++t)
      if (t != axis) v -= e_[q][t] * N[t];
    f[q] = v;
  }
}

// All populations rebuilt as equilibrium plus the regularized non-equilibrium
// part (Latt et al. 2008; at pressure faces with the inner node's velocity,
// lbm/boundaries.hpp): the unknowns' non-equilibrium is their opposite's,
// Pi^neq = sum e e f^neq, f = f^eq + w / (2 c_s^4) (e e - c_s^2 I) : Pi^neq,
// f^eq less Guo's first-order term w (e . Fc) / (2 c_s^2) (lbm/boundaries.hpp).
void LbmReference::regularize(double* f, int axis, int s, double rho, const double u[3],
                              const double Fc[3]) const {
  // The equilibrium with Guo's first-order term, whose momentum is rho_m u - Fc/2.
  std::vector<double> feq(Q_), neq(Q_);
  for (int q = 0; q < Q_; ++q)
    feq[q] = equilibrium(q, rho, u) - 1.5 * w_[q] * (e_[q][0] * Fc[0] + e_[q][1] * Fc[1] + e_[q][2] * Fc[2]);
  for (int q = 0; q < Q_; ++q) {
    const int k = s * e_[q][axis] > 0 ? opp_[q] : q;
    neq[q] = f[k] - feq[k];
  }
  double pi[3][3] = {};
  for (int q = 0; q < Q_; ++q)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) pi[a][b] += e_[q][a] * e_[q][b] * neq[q];
  for (int q = 0; q < Q_; ++q) {
    double qpi = 0.0;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) qpi += (e_[q][a] * e_[q][b] - (a == b ? 1.0 / 3.0 : 0.0)) * pi[a][b];
    f[q] = feq[q] + 4.5 * w_[q] * qpi;
  }
}

// The populations, one cell after another, as the checkpoint's grid field.
// Two fluids: red then blue per cell (the layout of lbm's checkpoint).
void LbmReference::save(const std::string& dir) {
  std::vector<double> p = f_;
  if (colours()) {
    p.resize(2 * f_.size());
    for (std::size_t c = 0; c < f_.size() / Q_; ++c)
      for (int q = 0; q < Q_; ++q) p[2 * c * Q_ + q] = r_[c * Q_ + q], p[(2 * c + 1) * Q_ + q] = b_[c * Q_ + q];
  }
  grid::save_cell_fields(comm_, dir + "/lbm.h5", time(), steps_, {n_[0], n_[1], n_[2]}, box_,
                         {{"populations", colours() ? 2 * Q_ : Q_, p}});
  grid::save_number(comm_, dir + "/lbm_max_u2.txt", max_u2_);  // the immersed boundaries' scale (as lbm's)
  grid::save_number(comm_, dir + "/lbm_offset.txt", 0.0);      // whole populations (lbm's one fluid: f - w)
}

void LbmReference::load(const std::string& dir, long steps, double) {
  const auto p = grid::load_cell_field(dir + "/lbm.h5", "populations", {n_[0], n_[1], n_[2]}, box_,
                                       colours() ? 2 * Q_ : Q_);
  steps_ = steps;
  max_u2_ = grid::load_number(dir + "/lbm_max_u2.txt", 0.0);
  if (!colours()) {  // lbm's one-fluid checkpoint holds f - w (lbm_offset.txt 1)
    f_ = p;
    if (grid::load_number(dir + "/lbm_offset.txt", 0.0) != 0.0)
      for (std::size_t n = 0; n < f_.size(); ++n) f_[n] += w_[n % Q_];
    return;
  }
  for (std::size_t c = 0; c < f_.size() / Q_; ++c)
    for (int q = 0; q < Q_; ++q) {
      r_[c * Q_ + q] = p[2 * c * Q_ + q], b_[c * Q_ + q] = p[(2 * c + 1) * Q_ + q];
      if (!solid_id_[c]) f_[c * Q_ + q] = r_[c * Q_ + q] + b_[c * Q_ + q];
    }
}

void LbmReference::moments(long c, double& rho, double u[3]) const {
  if (colours() && solid_id_[c]) {  // an interior solid: at rest, reference density
    rho = 1.0;
    u[0] = u[1] = u[2] = 0.0;
    return;
  }
  const double* f = &f_[c * Q_];
  rho = 0.0;
  double j[3] = {0, 0, 0};
  for (int q = 0; q < Q_; ++q) {
    rho += f[q];
    for (int d = 0; d < 3; ++d) j[d] += e_[q][d] * f[q];
  }
  // Stored f is post-collision: its momentum carries the whole force, so the
  // velocity of the step is (j - F/2) / rho_m.
  const double rho_m = s_.incompressible ? 1.0 : rho;
  // (the body force's half and the immersed boundaries'; a point-particle
  // source counts in full, as in lbm)
  for (int d = 0; d < 3; ++d)
    u[d] = (j[d] - 0.5 * (s_.force[d] + (ibm_force_.empty() ? 0.0 : ibm_force_[3 * c + d]))) / rho_m;
}

void LbmReference::advance(double dt) {
  const long n = std::lround(dt / s_.units.dt);
  for (long i = 0; i < n; ++i) {
    lbm::ramp_faces(s_.faces, steps_);
    step();
  }
  const Diagnostics d = diagnostics();
  if (!std::isfinite(d.mass))
    throw coupler::SolverError(fmt::format("lbm-reference: density is not finite at step {}", steps_));
  // Mach number (seed 000 eqs. 2.38 and 2.52), at the window's end: stop
  // above 0.3, as lbm does (it checks every step, and warns above 0.1).
  if (!(d.max_mach <= 0.3))
    throw coupler::SolverError(
        fmt::format("lbm-reference: Mach number {:.3f} at step {} exceeds 0.3 (max velocity "
                    "{:.4g} m/s); the lattice Boltzmann method is invalid there",
                    d.max_mach, steps_, d.max_velocity));
}

std::vector<output::GridField> LbmReference::fields(const config::StringList& names) {
  const long cells = n_[0] * n_[1] * n_[2];
  out_u_.resize(3 * cells);
  out_p_.resize(cells);
  out_rho_.resize(cells);
  for (long c = 0; c < cells; ++c) {
    double rho, u[3];
    moments(c, rho, u);
    for (int d = 0; d < 3; ++d) out_u_[3 * c + d] = u[d] * s_.units.velocity();
    out_p_[c] = s_.units.pressure_of(rho);
    out_rho_[c] = rho * s_.units.rho;
  }
  // Interior solids (1), partially saturated cells (psm), zero elsewhere; the
  // colour fraction (rho_r - rho_b) / (rho_r + rho_b), 1 for one fluid, 0 in solids.
  phase_fields(out_phase_, out_solid_);
  for (const auto& [c, s] : solid_) out_solid_[c] = s.fraction;
  std::vector<output::GridField> f;
  for (const auto& n : names) {
    if (n == "velocity") f.push_back({n, 3, out_u_});
    if (n == "pressure") f.push_back({n, 1, out_p_});
    if (n == "density") f.push_back({n, 1, out_rho_});
    if (n == "solid_fraction") f.push_back({n, 1, out_solid_});
    if (n == "phase") f.push_back({n, 1, out_phase_});
  }
  return f;
}

Diagnostics LbmReference::diagnostics() {
  Diagnostics d;
  const double vol = std::pow(s_.units.dx, 3), cu = s_.units.velocity();
  double umax = 0.0;
  for (long c = 0; c < n_[0] * n_[1] * n_[2]; ++c) {
    if (colours() && solid_id_[c]) continue;  // interior solids hold no fluid
    double rho, u[3];
    moments(c, rho, u);
    const double rho_m = s_.incompressible ? 1.0 : rho;
    const double m = rho_m * s_.units.rho * vol;
    d.mass += rho * s_.units.rho * vol;
    double uu = 0;
    for (int k = 0; k < 3; ++k) {
      d.momentum[k] += m * u[k] * cu;
      uu += u[k] * u[k];
    }
    d.kinetic_energy += 0.5 * m * uu * cu * cu;
    umax = std::max(umax, std::sqrt(uu));
  }
  d.max_velocity = umax * cu;
  d.max_mach = umax / std::sqrt(lbm::cs2);
  if (s_.tp.on) {
    const long cells = n_[0] * n_[1] * n_[2];
    std::vector<double> rho(cells), u(3 * cells), phase, solid;
    for (long c = 0; c < cells; ++c) moments(c, rho[c], &u[3 * c]);
    phase_fields(phase, solid);
    // The grains as the two-fluid collision takes them (set_solid's grain_eps_:
    // none in solids or next to open faces).
    d.extra = lbm::phase_values(s_.units, s_.cells, rho, u, phase, solid, grain_eps_, comm_);
  }
  return d;
}

std::vector<output::Series::Column> LbmReference::series_columns() const {
  return s_.tp.on ? lbm::phase_columns() : std::vector<output::Series::Column>{};
}

}  // namespace coflow::fluid
