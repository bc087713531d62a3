#include "fluid/fv/poisson_multigrid.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "fluid/fv/row_sums.hpp"
#include "fluid/fv/struct_system.hpp"
#include "fluid/grid/ghost_exchange.hpp"

namespace coflow::fluid::fv {

// One level: its decomposition, ghost exchange (one layer), couplings k = 1 /
// h^2 per axis (0 on an axis of one cell), the diagonal per cell, and the
// correction x, right-hand side b and residual r (padded like the block).
// Ghosts beyond a wall of the domain stay 0 in x (the operator's couplings
// there are zero); r and the coarser level's x get their mirror images there
// for the transfers (+ at zero normal gradient, - where phi = 0 at the face).
struct PoissonMultigrid::Level {
  Level(const coupler::Decomposition& d, int rank, MPI_Comm comm)
      : dec(d), ex(dec, rank, 1, 1, comm), blk(ex.block()) {}
  coupler::Decomposition dec;
  grid::GhostExchange ex;
  grid::Block blk;
  std::array<double, 3> k{0, 0, 0};
  std::array<std::array<double, 2>, 3> mirror{};  // per axis and side: 0 (no wall ghosts here), +1 or -1
  long sy = 0, sz = 0, parity = 0;
  std::vector<double> diag, inv_diag, x, b, r;
};

namespace {

using Level = PoissonMultigrid::Level;

// Every owned row of x: f(index of its first cell, j, k).
template <class F>
void for_rows(const Level& L, F&& f) {
  for (long k = 0; k < L.blk.extent[2]; ++k)
    for (long j = 0; j < L.blk.extent[1]; ++j) f(L.blk.idx(0, j, k), j, k);
}

void init_level(Level& L, const std::array<double, 3>& h, const std::array<bool, 6>& open) {
  const auto& cells = L.dec.cells();
  const auto& per = L.dec.periodic();
  for (int d = 0; d < 3; ++d) {
    L.k[d] = cells[d] > 1 ? 1.0 / (h[d] * h[d]) : 0.0;
    for (int side = 0; side < 2; ++side) {
      const bool at_wall = side == 0 ? L.blk.owned.lo[d] == 0 : L.blk.owned.hi[d] == cells[d];
      if (cells[d] > 1 && !per[d] && at_wall) L.mirror[d][side] = open[2 * d + side] ? -1.0 : 1.0;
    }
  }
  L.sy = L.blk.padded(0);
  L.sz = L.blk.padded(0) * L.blk.padded(1);
  L.parity = (L.blk.owned.lo[0] + L.blk.owned.lo[1] + L.blk.owned.lo[2]) & 1;
  const auto n = static_cast<std::size_t>(L.blk.cells());
  L.diag.assign(n, 0.0);
  L.inv_diag.assign(n, 0.0);
  L.x.assign(n, 0.0);
  L.b.assign(n, 0.0);
  L.r.assign(n, 0.0);
  for_rows(L, [&](long row, long j, long k) {
    const long at[3] = {0, j, k};
    for (long i = 0; i < L.blk.extent[0]; ++i) {
      double dg = 0.0;
      for (int d = 0; d < 3; ++d)
        for (int side = 0; side < 2; ++side) {
          const long a = d == 0 ? i : at[d];
          const bool edge = side == 0 ? a == 0 : a + 1 == L.blk.extent[d];
          if (L.k[d] == 0.0) continue;
          if (!(edge && L.mirror[d][side] != 0.0))
            dg += L.k[d];
          else if (L.mirror[d][side] < 0)
            dg += 2 * L.k[d];  // ghost -phi: phi = 0 on the face
        }
      L.diag[static_cast<std::size_t>(row + i)] = dg;
      L.inv_diag[static_cast<std::size_t>(row + i)] = 1.0 / dg;
    }
  });
}

// The mirror images beyond the domain's walls (after the exchange: corners
// take the images of exchanged ghosts, one axis after the other).
void mirror(const Level& L, std::vector<double>& v) {
  const auto& B = L.blk;
  for (int d = 0; d < 3; ++d)
    for (int side = 0; side < 2; ++side) {
      const double sign = L.mirror[d][side];
      if (sign == 0.0) continue;
      long lo[3], hi[3];
      for (int e = 0; e < 3; ++e) {
        lo[e] = -B.ghost[e];
        hi[e] = B.extent[e] + B.ghost[e];
      }
      const long ghost = side == 0 ? -1 : B.extent[d], inside = side == 0 ? 0 : B.extent[d] - 1;
      lo[d] = ghost;
      hi[d] = ghost + 1;
      long at[3];
      for (at[2] = lo[2]; at[2] < hi[2]; ++at[2])
        for (at[1] = lo[1]; at[1] < hi[1]; ++at[1])
          for (at[0] = lo[0]; at[0] < hi[0]; ++at[0]) {
            long in[3] = {at[0], at[1], at[2]};
            in[d] = inside;
            v[static_cast<std::size_t>(B.idx(at[0], at[1], at[2]))] =
                sign * v[static_cast<std::size_t>(B.idx(in[0], in[1], in[2]))];
          }
    }
}

// A level's couplings and strides in locals: a store through a double* may
// alias the level's own k, so a loop reading them through the level reloads
// them after every store (and does not vectorise).
struct Stencil {
  double k0, k1, k2;
  long sy, sz;
};
inline Stencil stencil(const Level& L) {
  return {L.k[0], L.k[1], L.k[2], L.sy, L.sz};
}

template <int D>
inline double neighbours(const Stencil& s, const double* x, long c) {
  double n = s.k0 * (x[c - 1] + x[c + 1]) + s.k1 * (x[c - s.sy] + x[c + s.sy]);
  if constexpr (D == 3) n += s.k2 * (x[c - s.sz] + x[c + s.sz]);
  return n;
}

// One colour of red-black Gauss-Seidel: the cells whose global i + j + k has
// the colour's parity.
template <int D>
void relax(Level& L, int colour) {
  double* __restrict x = L.x.data();
  const double* __restrict b = L.b.data();
  const double* __restrict inv = L.inv_diag.data();
  const Stencil s = stencil(L);
  const long nx = L.blk.extent[0], first = colour + L.parity;
  for_rows(L, [&](long row, long j, long k) {
    for (long i = (first + j + k) & 1; i < nx; i += 2)
      x[row + i] = (b[row + i] + neighbours<D>(s, x, row + i)) * inv[row + i];
  });
}

// The first colour's sweep from x = 0: its neighbours are all 0, so x = b / diag.
void relax_from_zero(Level& L) {
  double* __restrict x = L.x.data();
  const double* __restrict b = L.b.data();
  const double* __restrict inv = L.inv_diag.data();
  const long nx = L.blk.extent[0];
  for_rows(L, [&](long row, long j, long k) {
    for (long i = (L.parity + j + k) & 1; i < nx; i += 2) x[row + i] = b[row + i] * inv[row + i];
  });
}

// r = b - A x on the owned cells after a sweep of the first colour and then
// of the second, then r's ghosts (exchange and mirror). The second colour's
// cells have just solved their own equations, so their residual is 0 (up to
// rounding, taken as exactly 0): only the first colour's is computed.
template <int D>
void residual(Level& L) {
  L.ex.exchange(L.x);
  const double* __restrict x = L.x.data();
  const double* __restrict b = L.b.data();
  const double* __restrict dg = L.diag.data();
  double* __restrict r = L.r.data();
  const Stencil s = stencil(L);
  const long nx = L.blk.extent[0];
  for_rows(L, [&](long row, long j, long k) {
    std::fill_n(r + row, nx, 0.0);
    for (long c = row + ((L.parity + j + k) & 1); c < row + nx; c += 2)
      r[c] = b[c] - dg[c] * x[c] + neighbours<D>(s, x, c);
  });
  L.ex.exchange(L.r);
  mirror(L, L.r);
}

// Cell-centred trilinear weights along one axis, halved: the restriction is
// the prolongation's transpose over 2^D.
constexpr double kRestrict[4] = {0.125, 0.375, 0.375, 0.125};

// Coarse b = R (fine r): the 4^D fine cells around each coarse cell's
// children, taken one fine row at a time for a whole coarse row (the coarse
// cells innermost, so that the loops vectorise; each cell's terms are added in
// the same order as one cell at a time).
template <int D>
void restrict_residual(const Level& F, Level& C) {
  const double* __restrict r = F.r.data();
  double* __restrict cb = C.b.data();
  const long fy = F.sy, fz = F.sz, nx = C.blk.extent[0];
  for_rows(C, [&](long row, long J, long K) {
    double* __restrict out = cb + row;
    std::fill_n(out, nx, 0.0);
    // The fine cell below and left of the first coarse cell's children.
    const long first = F.blk.idx(-1, 2 * J - 1, D == 3 ? 2 * K - 1 : 0);
    for (int c = 0; c < (D == 3 ? 4 : 1); ++c) {
      const double wz = D == 3 ? kRestrict[c] : 1.0;
      for (int b = 0; b < 4; ++b) {
        const double* __restrict f = r + first + b * fy + (D == 3 ? c * fz : 0);
        const double w = wz * kRestrict[b];
        for (long I = 0; I < nx; ++I)
          out[I] += w * (0.125 * (f[2 * I] + f[2 * I + 3]) + 0.375 * (f[2 * I + 1] + f[2 * I + 2]));
      }
    }
  });
}

// Fine x += P (coarse x): each child from the 2^D coarse cells nearest to it
// (weights 3/4 and 1/4 per axis), the coarse ghosts exchanged and mirrored;
// one fine row at a time for a whole coarse row (coarse cells innermost).
template <int D>
void prolong_add(Level& C, Level& F) {
  C.ex.exchange(C.x);
  mirror(C, C.x);
  const double* __restrict xc = C.x.data();
  double* __restrict xf = F.x.data();
  const long cy = C.sy, cz = C.sz, fy = F.sy, fz = F.sz, nx = C.blk.extent[0];
  for_rows(C, [&](long row, long J, long K) {
    const long first = F.blk.idx(0, 2 * J, D == 3 ? 2 * K : 0);
    const double* __restrict a = xc + row;
    for (int z = 0; z < (D == 3 ? 2 : 1); ++z)
      for (int y = 0; y < 2; ++y) {
        const long oz = D == 3 ? (z ? cz : -cz) : 0, oy = y ? cy : -cy;
        double* __restrict f = xf + first + y * fy + (D == 3 ? z * fz : 0);
        for (long I = 0; I < nx; ++I)
          for (int x = 0; x < 2; ++x) {
            const long ox = x ? 1 : -1, c = I;
            double v =
                0.75 * (0.75 * a[c] + 0.25 * a[c + oy]) + 0.25 * (0.75 * a[c + ox] + 0.25 * a[c + ox + oy]);
            if constexpr (D == 3) {
              const double w = 0.75 * (0.75 * a[c + oz] + 0.25 * a[c + oz + oy]) +
                               0.25 * (0.75 * a[c + oz + ox] + 0.25 * a[c + oz + ox + oy]);
              v = 0.75 * v + 0.25 * w;
            }
            f[2 * I + x] += v;
          }
      }
  });
}

// The coarse decomposition of `dec` when every block halves exactly, into
// blocks of at least 2 cells along every axis with more than one cell (an
// axis is never coarsened to a single cell: the operators read both
// neighbours on every such axis).
bool halves(const coupler::Decomposition& dec, coupler::Decomposition& coarse) {
  coupler::Index3 cells{1, 1, 1};
  for (int d = 0; d < 3; ++d) {
    if (dec.cells()[d] == 1) continue;
    if (dec.cells()[d] % 2 != 0) return false;
    cells[d] = dec.cells()[d] / 2;
  }
  coarse = coupler::Decomposition(cells, dec.ranks(), dec.dims(), dec.periodic());
  for (int r = 0; r < dec.ranks(); ++r)
    for (int d = 0; d < 3; ++d) {
      const auto& f = dec.block(r);
      const auto& c = coarse.block(r);
      if (dec.cells()[d] == 1) continue;
      if (f.lo[d] % 2 != 0 || f.hi[d] % 2 != 0 || c.lo[d] * 2 != f.lo[d] || c.hi[d] * 2 != f.hi[d] ||
          c.extent(d) < 2)
        return false;
    }
  return true;
}

double dot(const Level& L, const std::vector<double>& a, const std::vector<double>& b, MPI_Comm comm) {
  double s = 0.0;
  const double* __restrict u = a.data(), * __restrict v = b.data();
  const long nx = L.blk.extent[0];
  for_rows(L, [&](long row, long, long) {
    row_sums(nx, &s, 1, [&](long i, auto p) { p[0] += u[row + i] * v[row + i]; });
  });
  MPI_Allreduce(MPI_IN_PLACE, &s, 1, MPI_DOUBLE, MPI_SUM, comm);
  return s;
}

}  // namespace

bool PoissonMultigrid::suits(const coupler::Decomposition& dec, const std::array<double, 3>& h) {
  double lo = 1e300, hi = 0.0;
  for (int d = 0; d < 3; ++d)
    if (dec.cells()[d] > 1) {
      lo = std::min(lo, h[static_cast<std::size_t>(d)]);
      hi = std::max(hi, h[static_cast<std::size_t>(d)]);
    }
  // x and y have more than one cell (as fv requires): the transfers step
  // along both.
  if (dec.cells()[0] < 2 || dec.cells()[1] < 2) return false;
  coupler::Decomposition coarse;
  return hi <= 2.0 * lo && halves(dec, coarse);
}

PoissonMultigrid::PoissonMultigrid(const coupler::Decomposition& dec, int rank, MPI_Comm comm,
                                   const std::array<double, 3>& h, const std::array<bool, 6>& open,
                                   Options opt)
    : opt_(std::move(opt)), comm_(comm), dims_(dec.cells()[2] == 1 ? 2 : 3) {
  if (!suits(dec, h))
    throw std::logic_error("PoissonMultigrid: the grid does not suit it (PoissonMultigrid::suits)");
  std::array<double, 3> hl = h;
  coupler::Decomposition d = dec, coarse;
  for (;;) {
    levels_.push_back(std::make_unique<Level>(d, rank, comm));
    init_level(*levels_.back(), hl, open);
    if (static_cast<int>(levels_.size()) > opt_.max_coarsenings || !halves(d, coarse)) break;
    d = coarse;
    for (auto& v : hl) v *= 2;
  }
  // The coarsest level: hypre's PFMG (one V-cycle from a zero guess).
  const Level& L = *levels_.back();
  singular_ = true;
  for (int a = 0; a < 3; ++a)
    if (dec.cells()[a] > 1 && !dec.periodic()[a] && (open[2 * a] || open[2 * a + 1])) singular_ = false;
  std::array<bool, 3> per{};
  for (int a = 0; a < 3; ++a) per[static_cast<std::size_t>(a)] = L.dec.periodic()[a] || L.dec.cells()[a] == 1;
  coarsest_ =
      std::make_unique<StructSystem>(comm, L.blk.owned, L.dec.cells(), per,
                                     StructSystem::Options{"pfmg", 0.0, 1, opt_.name + " (coarsest level)"});
  StructSystem::Rows m(static_cast<std::size_t>(L.blk.owned_cells()));
  long o = 0;
  for_rows(L, [&](long row, long j, long k) {
    for (long i = 0; i < L.blk.extent[0]; ++i, ++o) {
      const long at[3] = {i, j, k};
      m.diag[static_cast<std::size_t>(o)] = L.diag[static_cast<std::size_t>(row + i)];
      for (int a = 0; a < dims_; ++a) {
        const bool low_wall = at[a] == 0 && L.mirror[a][0] != 0.0;
        const bool high_wall = at[a] + 1 == L.blk.extent[a] && L.mirror[a][1] != 0.0;
        m.lower[static_cast<std::size_t>(a)][static_cast<std::size_t>(o)] = low_wall ? 0.0 : -L.k[a];
        m.upper[static_cast<std::size_t>(a)][static_cast<std::size_t>(o)] = high_wall ? 0.0 : -L.k[a];
      }
    }
  });
  coarsest_->set(m);
  coarse_b_.assign(static_cast<std::size_t>(L.blk.owned_cells()), 0.0);
  coarse_x_ = coarse_b_;
  p_.assign(levels_[0]->x.size(), 0.0);
  ap_ = p_;
  b_ = p_;
  x_ = p_;
}

PoissonMultigrid::~PoissonMultigrid() = default;

// Walls all round: the coarsest level's right-hand side and correction
// without their constant part (the null space), which the singular coarse
// cycle would otherwise amplify from round-off until the conjugate gradients
// stall (seen at 1e-8 on a 64 x 64 box). Both sides: the cycle stays symmetric.
void PoissonMultigrid::remove_mean(std::vector<double>& v) const {
  double s[2] = {0.0, static_cast<double>(v.size())};
  for (double e : v) s[0] += e;
  MPI_Allreduce(MPI_IN_PLACE, s, 2, MPI_DOUBLE, MPI_SUM, comm_);
  for (auto& e : v) e -= s[0] / s[1];
}

// The V-cycle on level l from a zero guess, for b on that level: red then
// black down, black then red up (the cycle is symmetric, as PCG needs).
void PoissonMultigrid::cycle(std::size_t l) {
  Level& L = *levels_[l];
  std::fill(L.x.begin(), L.x.end(), 0.0);
  if (l + 1 == levels_.size()) {
    long o = 0;
    for_rows(L, [&](long row, long, long) {
      for (long i = 0; i < L.blk.extent[0]; ++i, ++o)
        coarse_b_[static_cast<std::size_t>(o)] = L.b[static_cast<std::size_t>(row + i)];
    });
    if (singular_) remove_mean(coarse_b_);
    coarsest_->cycle(coarse_b_, coarse_x_);
    if (singular_) remove_mean(coarse_x_);
    o = 0;
    for_rows(L, [&](long row, long, long) {
      for (long i = 0; i < L.blk.extent[0]; ++i, ++o)
        L.x[static_cast<std::size_t>(row + i)] = coarse_x_[static_cast<std::size_t>(o)];
    });
    return;
  }
  Level& C = *levels_[l + 1];
  const bool three = dims_ == 3;
  relax_from_zero(L);  // x = 0: no ghosts to exchange
  L.ex.exchange(L.x);
  three ? relax<3>(L, 1) : relax<2>(L, 1);
  three ? residual<3>(L) : residual<2>(L);
  three ? restrict_residual<3>(L, C) : restrict_residual<2>(L, C);
  cycle(l + 1);
  three ? prolong_add<3>(C, L) : prolong_add<2>(C, L);
  L.ex.exchange(L.x);
  three ? relax<3>(L, 1) : relax<2>(L, 1);
  L.ex.exchange(L.x);
  three ? relax<3>(L, 0) : relax<2>(L, 0);
}

namespace {

// ap = A v on a level's owned cells; returns v . A v (this rank's part).
template <int D>
double apply_rows(const Level& L, const double* __restrict v, double* __restrict ap) {
  const double* __restrict dg = L.diag.data();
  const Stencil s = stencil(L);
  const long nx = L.blk.extent[0];
  double sum = 0.0;
  for_rows(L, [&](long row, long, long) {
    row_sums(nx, &sum, 1, [&](long i, auto a) {
      const long c = row + i;
      ap[c] = dg[c] * v[c] - neighbours<D>(s, v, c);
      a[0] += v[c] * ap[c];
    });
  });
  return sum;
}

}  // namespace

// ap = A v on the finest level (v's ghosts exchanged; beyond walls they stay
// 0); returns v . A v.
double PoissonMultigrid::apply(std::vector<double>& v) {
  Level& L = *levels_[0];
  L.ex.exchange(v);
  double s = dims_ == 3 ? apply_rows<3>(L, v.data(), ap_.data()) : apply_rows<2>(L, v.data(), ap_.data());
  MPI_Allreduce(MPI_IN_PLACE, &s, 1, MPI_DOUBLE, MPI_SUM, comm_);
  return s;
}

// Conjugate gradients (Hestenes & Stiefel 1952) on the finest level: r lives
// in its b (the V-cycle's right-hand side), z = M r in its x.
void PoissonMultigrid::solve(std::span<const double> b, std::span<double> x) {
  Level& L = *levels_[0];
  const long nx = L.blk.extent[0];
  std::vector<double>& r = L.b;
  long o = 0;
  for_rows(L, [&](long row, long, long) {
    for (long i = 0; i < nx; ++i, ++o) {
      const auto C = static_cast<std::size_t>(row + i), O = static_cast<std::size_t>(o);
      x_[C] = x[O];
      b_[C] = b[O];
    }
  });
  const double bb = dot(L, b_, b_, comm_);
  if (!std::isfinite(bb))  // NaN would skip the iterations below and report a residual of 0
    throw std::runtime_error(opt_.name + ": the right-hand side is not finite");
  if (bb == 0.0) std::fill(x_.begin(), x_.end(), 0.0);  // as hypre's PCG: x = 0 for b = 0
  apply(x_);
  for_rows(L, [&](long row, long, long) {
    for (long c = row; c < row + nx; ++c)
      r[static_cast<std::size_t>(c)] = b_[static_cast<std::size_t>(c)] - ap_[static_cast<std::size_t>(c)];
  });
  double rr = dot(L, r, r, comm_);
  const double target = std::max(opt_.tolerance * opt_.tolerance * bb, floor_ * floor_);
  iterations_ = 0;
  double rz = 0.0;
  while (rr > target && bb > 0.0 && iterations_ < opt_.max_iterations) {
    cycle(0);
    const double rz_new = dot(L, r, L.x, comm_);
    if (iterations_ == 0) {
      p_ = L.x;
    } else {
      const double beta = rz_new / rz;
      double* __restrict ps = p_.data();
      const double* __restrict z = L.x.data();
      for (std::size_t c = 0; c < p_.size(); ++c) ps[c] = z[c] + beta * ps[c];
    }
    rz = rz_new;
    const double alpha = rz / apply(p_);
    rr = 0.0;
    double* __restrict xs = x_.data(), * __restrict rs = r.data();
    const double* __restrict ps = p_.data(), * __restrict aps = ap_.data();
    for_rows(L, [&](long row, long, long) {
      row_sums(nx, &rr, 1, [&](long i, auto a) {
        const long c = row + i;
        xs[c] += alpha * ps[c];
        rs[c] -= alpha * aps[c];
        a[0] += rs[c] * rs[c];
      });
    });
    MPI_Allreduce(MPI_IN_PLACE, &rr, 1, MPI_DOUBLE, MPI_SUM, comm_);
    ++iterations_;
  }
  residual_ = bb > 0.0 ? std::sqrt(rr / bb) : 0.0;
  o = 0;
  for_rows(L, [&](long row, long, long) {
    for (long i = 0; i < nx; ++i, ++o) x[static_cast<std::size_t>(o)] = x_[static_cast<std::size_t>(row + i)];
  });
  if (!(rr <= target) && bb > 0.0)
    throw std::runtime_error(not_converged(opt_.name, residual_, iterations_, opt_.tolerance));
}

}  // namespace coflow::fluid::fv
