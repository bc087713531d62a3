#include "fluid/lbm/two_phase_core.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>

#include "coflow/session.hpp"
#include "fluid/grid/ghost_exchange.hpp"
#include "fluid/lbm/boundaries.hpp"
#include "fluid/lbm/colour_gradient.hpp"
#include "fluid/lbm/populations.hpp"
#include "fluid/lbm/psm_kernel.hpp"
#include "fluid/lbm/wall_tally.hpp"

namespace coflow::fluid::lbm {

namespace {

using coupler::Box;
using coupler::Decomposition;

constexpr std::uint8_t kWall = 255;  // a ghost cell beyond a wall face of the box

// Four neighbouring cells' red and blue populations q, stored side by side
// (lo = r0 b0 r1 b1, hi = r2 b2 r3 b3), as one colour per vector: red = r0 r2
// r1 r3, blue = b0 b2 b1 b3 (two in-lane unpacks; the lanes keep the order 0
// 2 1 3, and swap_middle takes a vector of the cells in order there and back).
using LaneMask = long __attribute__((vector_size(32)));
[[gnu::always_inline]] inline void split_pairs(Vec4 lo, Vec4 hi, Vec4& red, Vec4& blue) {
  red = __builtin_shuffle(lo, hi, LaneMask{0, 4, 2, 6});
  blue = __builtin_shuffle(lo, hi, LaneMask{1, 5, 3, 7});
}
[[gnu::always_inline]] inline void join_pairs(Vec4 red, Vec4 blue, Vec4& lo, Vec4& hi) {
  lo = __builtin_shuffle(red, blue, LaneMask{0, 4, 2, 6});
  hi = __builtin_shuffle(red, blue, LaneMask{1, 5, 3, 7});
}
[[gnu::always_inline]] inline Vec4 swap_middle(Vec4 v) {
  return __builtin_shuffle(v, LaneMask{0, 2, 1, 3});
}
// The colour field of four cells, in their order, from the sums of their
// pairs over the velocities: rho_r - rho_b, or with `phase` the same over
// rho_r + rho_b (colour_field()'s arithmetic per lane).
[[gnu::always_inline]] inline Vec4 colour_of(Vec4 lo, Vec4 hi, bool phase) {
  Vec4 red, blue;
  split_pairs(lo, hi, red, blue);
  return swap_middle(phase ? (red - blue) / (red + blue) : red - blue);
}

template <class L, bool Incompressible>
class TwoPhaseCore final : public LbmCore {
 public:
  TwoPhaseCore(const Setup& s, const Decomposition& dec, int rank, MPI_Comm comm)
      : s_(s), dec_(dec), ghosts_(dec, rank, 1, 1, comm) {
    colour_ = {s.tp.gamma, s.tp.beta, s.tau, s.tp.on ? s.tp.tau_blue : s.tau, s.trt, s.magic};
    const grid::Block& b = ghosts_.block();
    for (int d = 0; d < 3; ++d) {
      lay_.origin[d] = b.owned.lo[d];
      lay_.extent[d] = b.extent[d];
      lay_.ghost[d] = b.ghost[d];
      lay_.padded[d] = b.padded(d);
    }
    cells_ = b.cells();
    lay_.stride = cells_;  // unused here: pop_ holds two values a cell, indexed by at()
    for (int q = 0; q < L::Q; ++q) off_[q] = lay_.offset(L::e[q]);
    pop_.allocate(cells_, cells_);
    pop_.halo.build(lay_, dec_, rank, comm);
    phi_.assign(static_cast<std::size_t>(cells_), 0.0);
    mark_solids();
    if (s.tp.surface) find_links();
    build_tally();
    if (s.tp.geometric) find_wetted();
    find_plain();
    grain_.assign(static_cast<std::size_t>(cells_), 0);
    if (s.tp.geometric) {
      eps_.assign(static_cast<std::size_t>(cells_), 0.0);
      grain_cos_.assign(static_cast<std::size_t>(cells_), 0.0);
      grain_wet_index_.assign(static_cast<std::size_t>(cells_), -1);
      find_owned();
    }
    initialise();
  }

  void step() override {
    pop_.halo.post(pop_.f.data(), 2 * cells_);
    pop_.halo.finish(pop_.f.data(), 2 * cells_);
    stream();
    if (hook_) hook_();  // immersed boundaries: the streamed populations are in `next`
    colour_grains();
    if (!one_colour_) ghosts_.exchange(phi_);  // one colour: the gradient changes nothing (red_collide_lanes)
    fill_open_ghosts();
    max_u2_ = 0.0;
    const auto one = [&](long i, long j, long k, long x) {
      if (!solid_[x] && !grain_[x]) collide_cell(i, j, k, x);
    };
    if (hook_ && src_.empty())  // every cell streamed into `next`: the forced ones one at a time
      for_rows([&](long x) { return plain_pull_[x] && !special_[x] && !forced_cell_[x]; },
               [&](long x) { collide4<false>(x); }, one);
    else
      for_rows([&](long x) { return plain(x); },
               [&](long x) { one_colour_ ? collide4<true, false>(x) : collide4<true>(x); },
               [&](long i, long j, long k, long x) { return collide4_cells(i, j, k, x); }, one);
    pop_.swap();
  }

  void macroscopic(std::vector<double>& u, std::vector<double>& rho) const override {
    u.assign(3 * static_cast<std::size_t>(owned_cells()), 0.0);
    rho.assign(static_cast<std::size_t>(owned_cells()), 1.0);
    long c = 0;
    for_owned([&](long, long, long, long x) {
      if (!solid_[x]) {
        double r = 0.0, j[3] = {0.0, 0.0, 0.0};
        for (int q = 0; q < L::Q; ++q) {
          const double f = pop_.f[at(q, x)] + pop_.f[at(q, x) + 1];
          r += f;
          for (int d = 0; d < 3; ++d) j[d] += L::e[q][d] * f;
        }
        const double rho_m = Incompressible ? 1.0 : r;
        // As the one-fluid core: half the body force and of an immersed
        // boundary's force out (Guo), a source's impulse counted in full.
        const double* e = cell_force_.empty() ? nullptr : &cell_force_[static_cast<std::size_t>(3 * c)];
        for (int d = 0; d < 3; ++d) u[3 * c + d] = (j[d] - 0.5 * (s_.force[d] + (e ? e[d] : 0.0))) / rho_m;
        rho[c] = r;
      }
      ++c;
    });
  }

  bool phase(std::vector<double>& out) const override {
    out.assign(static_cast<std::size_t>(owned_cells()), 0.0);
    long c = 0;
    for_owned([&](long, long, long, long x) {
      if (!solid_[x]) {
        double r = 0.0, b = 0.0;
        for (int q = 0; q < L::Q; ++q) r += pop_.f[at(q, x)], b += pop_.f[at(q, x) + 1];
        out[c] = (r - b) / (r + b);
      }
      ++c;
    });
    return true;
  }
  bool solid_mask(std::vector<double>& out) const override {
    out.assign(static_cast<std::size_t>(owned_cells()), 0.0);
    long c = 0;
    for_owned([&](long, long, long, long x) { out[c++] = solid_[x] ? 1.0 : 0.0; });
    return true;
  }
  bool grain_fractions(std::vector<double>& out) const override {
    out.assign(static_cast<std::size_t>(owned_cells()), 0.0);
    for (std::size_t n = 0; n < grains_.size(); ++n)
      out[static_cast<std::size_t>(grain_cells_[n])] = grains_[n].eps;
    return true;
  }

  double max_u2() const override { return max_u2_; }
  void set_max_u2(double u2) override { max_u2_ = u2; }
  int q() const override { return 2 * L::Q; }
  long first_nonfinite() const override {
    long c = 0, found = -1;
    for_owned([&](long, long, long, long x) {
      for (int q = 0; q < L::Q && found < 0 && !solid_[x]; ++q)
        if (!std::isfinite(pop_.f[at(q, x)]) || !std::isfinite(pop_.f[at(q, x) + 1])) found = c;
      ++c;
    });
    return found;
  }
  // Red then blue, per owned cell.
  void get_populations(std::vector<double>& out) const override {
    out.clear();
    for_owned([&](long, long, long, long x) {
      for (int q = 0; q < L::Q; ++q) out.push_back(pop_.f[at(q, x)]);
      for (int q = 0; q < L::Q; ++q) out.push_back(pop_.f[at(q, x) + 1]);
    });
  }
  void set_populations(const std::vector<double>& in) override {
    std::size_t o = 0;
    for_owned([&](long, long, long, long x) {
      for (int q = 0; q < L::Q; ++q) pop_.f[at(q, x)] = in[o++];
      for (int q = 0; q < L::Q; ++q) pop_.f[at(q, x) + 1] = in[o++];
    });
  }
  // The grains' cells of the next steps: fluid cells (not in interior solids,
  // not on open faces, which keep their closure as in one fluid) with their
  // solid fraction and wetting.
  void set_psm(std::span<const long> cells, std::span<const double> fraction,
               std::span<const double> wetting) override {
    for (const Grain& m : grains_) special_[m.x] = static_special_[m.x], grain_[m.x] = 0;
    grains_.clear();
    grain_cells_.clear();
    for (std::size_t n = 0; n < cells.size(); ++n) {
      const long x = block_index(cells[n]);
      bool open = false;
      for (int q = 1; q < L::Q; ++q) open = open || open_[x + off_[q]];
      if (!solid_[x] && !open)
        grains_.push_back({x, fraction[n], wetting[n]}), grain_cells_.push_back(cells[n]);
    }
    if (s_.tp.geometric) find_grain_wetted();
    // Grain cells take the one-cell passes: the streaming stores their pulled
    // populations (the seed's wetting reads them in colour_grains), and the
    // collision leaves them to psm(), which collides them once.
    for (const Grain& m : grains_) special_[m.x] = 1, grain_[m.x] = 1;
  }
  // Partially saturated cells (psm_kernel.hpp, psm_colour_collide) on the cells
  // of the step just taken: the same streamed populations pulled again from
  // the previous arrays (their ghosts still hold the halo), the colour
  // gradient of the step, and collided (the step left them to this).
  void psm(std::span<const long> cells, std::span<const double> fraction, std::span<const double> us,
           std::span<double> gain) override {
    for (std::size_t n = 0; n < cells.size(); ++n) {
      const long c = cells[n], x = block_index(c);
      bool open = false;
      for (int q = 1; q < L::Q; ++q) open = open || open_[x + off_[q]];
      if (solid_[x] || open) continue;
      double r[L::Q], b[L::Q], g[3], F[3], kept[2] = {0.0, 0.0};
      for (int q = 0; q < L::Q; ++q) {
        const long src = x - off_[q];
        const bool back = solid_[src] != 0;
        r[q] = back ? pop_.next[at(L::opp[q], x)] : pop_.next[at(q, src)];
        b[q] = back ? pop_.next[at(L::opp[q], x) + 1] : pop_.next[at(q, src) + 1];
        if (const double delta = back ? link_delta(x, q) : -1.0; delta >= 0.0)  // as stream_cell
          interpolate(pop_.next.data(), x, q, delta, r[q], b[q], kept);
      }
      r[0] += kept[0], b[0] += kept[1];
      gradient(x, g);
      force(c, F);
      const double uu =
          psm_colour_collide<L, Incompressible>(r, b, g, colour_, F, fraction[n], &us[3 * n], &gain[3 * n]);
      max_u2_ = nan_max(max_u2_, uu);
      for (int q = 0; q < L::Q; ++q) pop_.f[at(q, x)] = r[q], pop_.f[at(q, x) + 1] = b[q];
    }
  }
  void set_source(std::span<const double> force) override {
    src_.assign(force.begin(), force.end());
    fused_ = src_.empty() && !hook_;
  }
  // Immersed boundaries (LbmCore::set_hook): with a hook every cell's pulled
  // populations are stored in `next` (streamed_velocity reads them), four
  // cells at a time where plain, and the forced cells collide one at a time
  // with their force (step(), stream()).
  void set_hook(std::function<void()> hook) override {
    hook_ = std::move(hook);
    forced_cell_.assign(static_cast<std::size_t>(cells_), 0);  // before any set_cell_forces
    fused_ = src_.empty() && !hook_;
  }
  void streamed_velocity(std::span<const long> cells, std::span<double> u,
                         std::span<double> rho) const override {
    for (std::size_t n = 0; n < cells.size(); ++n) {
      const long c = cells[n], x = block_index(c);
      double r = 0.0, j[3] = {0.0, 0.0, 0.0}, F[3];
      for (int q = 0; q < L::Q; ++q) {
        const double f = pop_.next[at(q, x)] + pop_.next[at(q, x) + 1];
        r += f;
        for (int d = 0; d < 3; ++d) j[d] += L::e[q][d] * f;
      }
      drive(c, F);  // not the last step's forcing
      const double rho_m = Incompressible ? 1.0 : r;
      for (int d = 0; d < 3; ++d) u[3 * n + d] = (j[d] + 0.5 * F[d]) / rho_m;
      rho[n] = rho_m;
    }
  }
  void set_cell_forces(std::span<const long> cells, std::span<const double> force) override {
    if (cell_force_.empty()) cell_force_.assign(3 * static_cast<std::size_t>(owned_cells()), 0.0);
    if (forced_cell_.empty()) forced_cell_.assign(static_cast<std::size_t>(cells_), 0);
    for (long c : forced_) {
      for (int d = 0; d < 3; ++d) cell_force_[static_cast<std::size_t>(3 * c + d)] = 0.0;
      forced_cell_[static_cast<std::size_t>(block_index(c))] = 0;
    }
    forced_.assign(cells.begin(), cells.end());
    for (std::size_t n = 0; n < cells.size(); ++n) {
      for (int d = 0; d < 3; ++d) cell_force_[static_cast<std::size_t>(3 * cells[n] + d)] = force[3 * n + d];
      forced_cell_[static_cast<std::size_t>(block_index(cells[n]))] = 1;
    }
  }
  coupler::ExactSums take_wall_momentum(double unit) override { return tally_.take(unit); }

 private:
  long owned_cells() const { return lay_.extent[0] * lay_.extent[1] * lay_.extent[2]; }
  // An owned cell's index (k ny + j) nx + i in the block with its ghosts.
  long block_index(long c) const {
    const long nx = lay_.extent[0], ny = lay_.extent[1];
    return lay_.idx(c % nx, (c / nx) % ny, c / (nx * ny));
  }
  // The body force and the momentum source of owned cell c.
  void drive(long c, double F[3]) const {
    for (int d = 0; d < 3; ++d) F[d] = s_.force[d] + (src_.empty() ? 0.0 : src_[3 * c + d]);
  }
  // The same and the immersed boundaries' force (set by this step's hook).
  void force(long c, double F[3]) const {
    drive(c, F);
    if (!cell_force_.empty())
      for (int d = 0; d < 3; ++d) F[d] += cell_force_[static_cast<std::size_t>(3 * c + d)];
  }
  template <class F>
  void for_owned(F&& f) const {
    for (long k = 0; k < lay_.extent[2]; ++k)
      for (long j = 0; j < lay_.extent[1]; ++j)
        for (long i = 0; i < lay_.extent[0]; ++i) f(i, j, k, lay_.idx(i, j, k));
  }

  // Solid cells of the block and its ghosts: interior solids from the global
  // map (periodic images wrapped), the box's walls beyond non-periodic faces;
  // each takes its fixed colour phi_s = cos(theta) (seed 000, "Molhabilidade").
  void mark_solids() {
    solid_.assign(static_cast<std::size_t>(cells_), 0);
    open_.assign(static_cast<std::size_t>(cells_), 0);
    const auto& n = s_.cells;
    for (long k = -lay_.ghost[2]; k < lay_.extent[2] + lay_.ghost[2]; ++k)
      for (long j = -lay_.ghost[1]; j < lay_.extent[1] + lay_.ghost[1]; ++j)
        for (long i = -lay_.ghost[0]; i < lay_.extent[0] + lay_.ghost[0]; ++i) {
          long g[3] = {lay_.origin[0] + i, lay_.origin[1] + j, lay_.origin[2] + k}, in[3] = {i, j, k};
          std::uint8_t id = 0;
          const Face* open = nullptr;
          for (int d = 0; d < 3; ++d) {
            if (g[d] >= 0 && g[d] < n[d]) continue;
            const Face& face = s_.faces[2 * d + (g[d] < 0 ? 0 : 1)];
            if (face.type == FaceType::periodic) {
              g[d] = (g[d] + n[d]) % n[d];
            } else if (face.type == FaceType::wall) {
              id = kWall;
            } else {
              open = &face;
              in[d] += g[d] < 0 ? 1 : -1;  // the face's cell
            }
          }
          const long x = lay_.idx(i, j, k);
          if (id == 0 && open) {  // beyond a pressure, velocity or outflow face
            open_[x] = 1;
            open_ghosts_.push_back({x, open->phase_given ? -1 : lay_.idx(in[0], in[1], in[2]), open->phase});
            continue;
          }
          if (id == 0 && s_.tp.any_solid())
            id = (*s_.tp.solids)[static_cast<std::size_t>((g[2] * n[1] + g[1]) * n[0] + g[0])];
          solid_[x] = id;
          if (id) phi_[x] = id == kWall ? s_.tp.wall_phase : s_.tp.solid_phase.at(id);
        }
  }

  // Beyond open faces the colour field is the entering phase where the face
  // gives one, else the face cell's (no gradient across the face).
  void fill_open_ghosts() {
    for (const auto& g : open_ghosts_) phi_[g.x] = g.source >= 0 ? phi_[g.source] : g.phase;
  }

  // Interpolated bounce-back: where each link of an owned fluid cell into an
  // interior solid crosses the solids' surface (fluid/solid_surface.hpp), for
  // the population q that the link brings in from x - e_q.
  void find_links() {
    link_index_.assign(static_cast<std::size_t>(cells_), -1);
    for_owned([&](long i, long j, long k, long x) {
      if (solid_[x]) return;
      const std::array<long, 3> g{lay_.origin[0] + i, lay_.origin[1] + j, lay_.origin[2] + k};
      for (int q = 1; q < L::Q; ++q) {
        const std::uint8_t id = solid_[x - off_[q]];
        if (id == 0 || id == kWall) continue;
        if (link_index_[x] < 0) {
          link_index_[x] = static_cast<int>(link_delta_.size());
          link_delta_.resize(link_delta_.size() + L::Q, -1.0);
        }
        const int toward[3] = {-L::e[q][0], -L::e[q][1], -L::e[q][2]};
        link_delta_[static_cast<std::size_t>(link_index_[x] + q)] = s_.tp.surface->fraction(g, toward, id);
      }
    });
  }

  // The owned fluid cells next to solids (geometric wetting): the solid's unit
  // normal into the fluid, n_s = -sum_q w_q e_q s(x + e_q) normalised (s = 1 in
  // solids), and cos(theta) averaged over the solid neighbours with the same
  // weights (phi_ holds cos(theta) in solid cells).
  void find_wetted() {
    wet_index_.assign(static_cast<std::size_t>(cells_), -1);
    for_owned([&](long, long, long, long x) {
      if (solid_[x]) return;
      Wet w{{0.0, 0.0, 0.0}, 0.0};
      double weight = 0.0;
      for (int q = 1; q < L::Q; ++q) {
        if (!solid_[x + off_[q]]) continue;
        for (int d = 0; d < 3; ++d) w.ns[d] -= L::w[q] * L::e[q][d];
        w.cos_theta += L::w[q] * phi_[x + off_[q]];
        weight += L::w[q];
      }
      if (weight == 0.0) return;
      const double n = std::sqrt(w.ns[0] * w.ns[0] + w.ns[1] * w.ns[1] + w.ns[2] * w.ns[2]);
      for (int d = 0; d < 3; ++d) w.ns[d] = n > 0.0 ? w.ns[d] / n : 0.0;
      w.cos_theta /= weight;
      wet_index_[x] = static_cast<int>(wet_.size());
      wet_.push_back(w);
    });
  }

  // Geometric wetting of grains: the grains' fraction and cos(theta) over the
  // block and its ghosts, then the cells (not wholly covered) that hold or
  // touch a grain, with the solids' unit normal n_s = -sum_q w_q e_q eps(x +
  // e_q) normalised (eps = 1 in solid cells) and cos(theta) averaged with the
  // weights w_q eps (solid cells: their colour, which is cos(theta)).
  void find_grain_wetted() {
    for (const long x : grain_set_) eps_[x] = 0.0, grain_cos_[x] = 0.0;
    for (const long x : grain_touched_) grain_wet_index_[x] = -1, special_[x] = static_special_[x];
    grain_set_.clear();
    grain_wet_.clear();
    for (const Grain& m : grains_) eps_[m.x] = m.eps, grain_cos_[m.x] = m.wetting, grain_set_.push_back(m.x);
    ghosts_.exchange(eps_);
    ghosts_.exchange(grain_cos_);
    // The owned cells in or next to a grain cell (owned, or a ghost from
    // another rank), each once.
    grain_touched_.clear();
    // A ghost cell's neighbour may lie beyond the block: before its first
    // plane or after its last (the other axes' overruns land on ghost or
    // padding cells, which are not owned).
    const auto around = [&](long x) {
      for (int q = 0; q < L::Q; ++q) {
        const long n = x + off_[q];
        if (n >= 0 && n < cells_ && owned_[n] && !touched_[n]) touched_[n] = 1, grain_touched_.push_back(n);
      }
    };
    for (const Grain& m : grains_) around(m.x);
    for (const long x : ghost_cells_)
      if (eps_[x] > 0.0) around(x);
    for (const long x : grain_touched_) {
      touched_[x] = 0;
      wet_by_grain(x);
    }
  }

  // One owned cell of find_grain_wetted(): its normal and angle where it is
  // not wholly covered and holds or touches a grain.
  void wet_by_grain(long x) {
    if (solid_[x] || eps_[x] >= 1.0) return;
    bool grain = eps_[x] > 0.0;
    Wet w{{0.0, 0.0, 0.0}, 0.0};
    double weight = 0.0;
    for (int q = 1; q < L::Q; ++q) {
      const long n = x + off_[q];
      const double e = solid_[n] ? 1.0 : eps_[n];
      grain = grain || (!solid_[n] && eps_[n] > 0.0);
      for (int d = 0; d < 3; ++d) w.ns[d] -= L::w[q] * e * L::e[q][d];
      w.cos_theta += L::w[q] * e * (solid_[n] ? phi_[n] : grain_cos_[n]);
      weight += L::w[q] * e;
    }
    if (!grain) return;
    const double len = std::sqrt(w.ns[0] * w.ns[0] + w.ns[1] * w.ns[1] + w.ns[2] * w.ns[2]);
    for (int d = 0; d < 3; ++d) w.ns[d] = len > 0.0 ? w.ns[d] / len : 0.0;
    w.cos_theta = weight > 0.0 ? w.cos_theta / weight : 0.0;
    grain_wet_index_[x] = static_cast<int>(grain_wet_.size());
    grain_wet_.push_back(w);
    special_[x] = 1;
  }

  // Owned cells (1) of the block with its ghosts, and the ghost cells' list.
  void find_owned() {
    owned_.assign(static_cast<std::size_t>(cells_), 0);
    touched_.assign(static_cast<std::size_t>(cells_), 0);
    for_owned([&](long, long, long, long x) { owned_[x] = 1; });
    for (long k = -lay_.ghost[2]; k < lay_.extent[2] + lay_.ghost[2]; ++k)
      for (long j = -lay_.ghost[1]; j < lay_.extent[1] + lay_.ghost[1]; ++j)
        for (long i = -lay_.ghost[0]; i < lay_.extent[0] + lay_.ghost[0]; ++i)
          if (!owned_[lay_.idx(i, j, k)]) ghost_cells_.push_back(lay_.idx(i, j, k));
  }

  // Cells the four-cell passes take: fluid cells all of whose neighbours are
  // fluid (pulled without bounce-back or closure), and fluid cells without
  // wetting (the plain colour gradient). Grains add their cells in
  // find_grain_wetted().
  void find_plain() {
    plain_pull_.assign(static_cast<std::size_t>(cells_), 0);
    static_special_.assign(static_cast<std::size_t>(cells_), 1);
    for_owned([&](long, long, long, long x) {
      if (solid_[x]) return;
      bool all_fluid = true;
      for (int q = 1; q < L::Q; ++q) all_fluid = all_fluid && !solid_[x + off_[q]] && !open_[x + off_[q]];
      plain_pull_[x] = all_fluid ? 1 : 0;
      static_special_[x] = !wet_index_.empty() && wet_index_[x] >= 0 ? 1 : 0;
    });
    special_ = static_special_;
  }

  // Each colour at the equilibrium of its share of the cell's density, with
  // its share of the body force's half (post-collision momentum rho u + F/2).
  void initialise() {
    for_owned([&](long i, long j, long k, long x) {
      if (solid_[x]) return;
      const long g[3] = {lay_.origin[0] + i, lay_.origin[1] + j, lay_.origin[2] + k};
      double rho, u[3];
      s_.initial(g[0], g[1], g[2], rho, u);
      const double psi = s_.tp.on ? s_.tp.initial_phase(g[0], g[1], g[2]) : 1.0;
      for (int q = 0; q < L::Q; ++q) {
        const double feq =
            equilibrium<L, Incompressible>(q, rho, u) + L::w[q] + half_force<L>(q, s_.force.data());
        pop_.f[at(q, x)] = 0.5 * (1.0 + psi) * feq;
        pop_.f[at(q, x) + 1] = 0.5 * (1.0 - psi) * feq;
      }
    });
  }

  // Pull streaming of both colours into `next` (seed 000 eqs. 2.64-2.65), with
  // half-way bounce-back from solid cells (eq. 2.44; interpolated at interior
  // solids with fluid.lbm.bounce_back: interpolated or central), and (two
  // fluids) the colour field of the pulled populations.
  void stream() {
    const auto one = [&](long i, long j, long k, long x) {
      if (!solid_[x]) stream_cell(i, j, k, x);
    };
    if (hook_ && src_.empty())  // immersed boundaries: every cell's populations into `next`
      for_rows([&](long x) { return plain_pull_[x] && !special_[x]; }, [&](long x) { stream4(x); }, one);
    else if (one_colour_)  // the four-cell collision reads no colour field
      for_rows([&](long x) { return plain(x); }, [](long) {}, one);
    else
      for_rows([&](long x) { return plain(x); }, [&](long x) { colour4(x); }, one);
  }

  // Rows of owned cells, four at a time along x: `four` where `plain` holds for
  // all four, else (and for the row's last cells) `one` per cell. A cell's
  // arithmetic is the same either way (the lanes are independent), so that
  // the results do not depend on where a block starts.
  // `group`, where given, may take four cells that are not all plain at once
  // (it returns false where it does not).
  template <class Plain, class Four, class One>
  void for_rows(Plain&& plain, Four&& four, One&& one) {
    for_rows(
        plain, four, [](long, long, long, long) { return false; }, one);
  }
  template <class Plain, class Four, class Group, class One>
  void for_rows(Plain&& plain, Four&& four, Group&& group, One&& one) {
    const long nx = lay_.extent[0];
    for (long k = 0; k < lay_.extent[2]; ++k)
      for (long j = 0; j < lay_.extent[1]; ++j) {
        long i = 0;
        for (; i + 4 <= nx; i += 4) {
          const long x = lay_.idx(i, j, k);
          if (plain(x) && plain(x + 1) && plain(x + 2) && plain(x + 3)) {
            four(x);
            continue;
          }
          if (group(i, j, k, x)) continue;
          for (long m = 0; m < 4; ++m) one(i + m, j, k, x + m);
        }
        for (; i < nx; ++i) one(i, j, k, lay_.idx(i, j, k));
      }
  }

  // A cell the four-cell passes take: a fluid cell whose neighbours are all
  // fluid (pulled without bounce-back or closure), without wetting or grains
  // (the plain colour gradient), in a fluid without a momentum source or
  // immersed boundaries (fused_).
  bool plain(long x) const { return fused_ && plain_pull_[x] && !special_[x]; }

  // Four plain cells: the colour field of their pulled populations (stream_cell's
  // sum); collide4 pulls them again, so nothing is stored in between.
  void colour4(long x) {
    // Locals, not members: the stores below are byte copies, after which the
    // compiler would reload every member they might alias.
    const long n = cells_;
    const double* f = pop_.f.data();
    Vec4 lo = splat<Vec4>(0.0), hi = lo;  // sums of r0 b0 r1 b1 and of r2 b2 r3 b3
#pragma GCC unroll 32
    for (int q = 0; q < L::Q; ++q) {
      const double* p = f + 2 * (q * n + x - off_[q]);
      lo += detail::get(p);
      hi += detail::get(p + 4);
      prefetch_pulled(p + prefetch_ahead);  // the values ahead: eight cache lines, 32 cells
    }
    detail::put<false>(&phi_[x], colour_of(lo, hi, s_.tp.phase_field));
  }

  // Four plain cells pulled into `next` with their colour field (stream_cell's
  // arithmetic on four lanes), for a collision that reads them there.
  void stream4(long x) {
    const long n = cells_;  // locals: see colour4
    const double* f = pop_.f.data();
    double* next = pop_.next.data();
    Vec4 lo = splat<Vec4>(0.0), hi = lo;
#pragma GCC unroll 32
    for (int q = 0; q < L::Q; ++q) {
      const double* p = f + 2 * (q * n + x - off_[q]);
      const Vec4 a = detail::get(p), c = detail::get(p + 4);
      detail::put<false>(next + 2 * (q * n + x), a);
      detail::put<false>(next + 2 * (q * n + x) + 4, c);
      lo += a;
      hi += c;
    }
    detail::put<false>(&phi_[x], colour_of(lo, hi, s_.tp.phase_field));
  }

  // Four plain cells collided (collide_cell's arithmetic on four lanes), into
  // `next`: pulled from the current populations (Pulled), or already streamed
  // into `next` by stream4 (with immersed boundaries stream() stores every
  // cell there, for the forcing to read; these cells take no cell force). The
  // lanes run in the order 0 2 1 3 of the cells (split_pairs). Blue false: one
  // fluid (no blue, no surface tension; interior solids and immersed bodies do
  // not run together): red_collide_lanes, without the colour field and its
  // gradient; blue stored as the +0 that colour_collide_lanes makes of it.
  template <bool Pulled, bool Blue = true>
  void collide4(long x) {
    const long n = cells_;  // locals: see colour4
    const double *f = pop_.f.data(), *phi = phi_.data();
    double* next = pop_.next.data();
    const long* off = off_;
    const Vec4 zero = splat<Vec4>(0.0);
    Vec4 r[L::Q], b[L::Q], g[3] = {zero, zero, zero};
    if constexpr (Blue) {
#pragma GCC unroll 32
      for (int q = 1; q < L::Q; ++q) {
        const Vec4 ph = detail::get(phi + x + off[q]);
        for (int d = 0; d < 3; ++d) g[d] += L::e[q][d] * ph;
      }
      for (int d = 0; d < 3; ++d) g[d] = swap_middle(g[d]);
    }
    const double F[3] = {s_.force[0] + 0.0, s_.force[1] + 0.0, s_.force[2] + 0.0};  // as force() without a source
#pragma GCC unroll 32
    for (int q = 0; q < L::Q; ++q) {
      const double* p = Pulled ? f + 2 * (q * n + x - off[q]) : next + 2 * (q * n + x);
      split_pairs(detail::get(p), detail::get(p + 4), r[q], b[q]);
      if constexpr (Pulled) prefetch_pulled(p + prefetch_ahead);
    }
    const Vec4 uu = Blue ? colour_collide_lanes<L, Incompressible, Vec4>(r, b, g, colour_, F)
                         : red_collide_lanes<L, Incompressible, Vec4>(r, colour_, F);
    double most = max_u2_;
    for (int m = 0; m < 4; ++m) most = nan_max(most, uu[m]);
    max_u2_ = most;
#pragma GCC unroll 32
    for (int q = 0; q < L::Q; ++q) {
      Vec4 lo, hi;
      join_pairs(r[q], Blue ? b[q] : zero, lo, hi);
      detail::put<false>(next + 2 * (q * n + x), lo);
      detail::put<false>(next + 2 * (q * n + x) + 4, hi);
    }
  }

  // Where red population q of cell x sits (blue: the next value).
  long at(int q, long x) const {
    return 2 * (q * cells_ + x);
  }

  // Pull streaming of one fluid cell (see stream()).
  void stream_cell(long i, long j, long k, long x) {
    {
      bool unknown[L::Q], any = false;
      int last_slot = -1;  // the wall tally's sums of this cell for last_slot
      double* m = nullptr;
      double kept[2] = {0.0, 0.0};  // what the interpolated links took from each colour
      for (int q = 0; q < L::Q; ++q) {
        const long src = x - off_[q];
        double r = 0.0, b = 0.0;
        unknown[q] = open_[src] != 0;
        any = any || unknown[q];
        if (solid_[src]) {
          r = pop_.f[at(L::opp[q], x)];
          b = pop_.f[at(L::opp[q], x) + 1];
          // Ladd's momentum exchange, relative to the fluid at rest at the
          // reference density (whose push on a closed solid sums to zero).
          double moved = r + b - L::w[q];
          if (const double delta = link_delta(x, q); delta >= 0.0)
            moved = interpolate(pop_.f.data(), x, q, delta, r, b, kept);
          const int slot = solid_[src] == kWall ? wall_face(i, j, k, q) : 5 + solid_[src];
          if (slot >= 0) {
            if (slot != last_slot)  // most cells border one wall or solid: looked up once
              m = tally_.at((k * lay_.extent[1] + j) * lay_.extent[0] + i, slot), last_slot = slot;
            for (int a = 0; a < 3; ++a) m[a] -= 2.0 * moved * L::e[q][a];
          }
        } else if (!unknown[q]) {
          r = pop_.f[at(q, src)];
          b = pop_.f[at(q, src) + 1];
        }
        pop_.next[at(q, x)] = r;
        pop_.next[at(q, x) + 1] = b;
      }
      pop_.next[at(0, x)] += kept[0];  // each colour's mass kept (see interpolate)
      pop_.next[at(0, x) + 1] += kept[1];
      if (any) close_cell(i, j, k, x, unknown);
      if (one_colour_) return;  // nothing reads the colour field (the plain cells store none either)
      double rr = 0.0, bb = 0.0;
      for (int q = 0; q < L::Q; ++q) rr += pop_.next[at(q, x)], bb += pop_.next[at(q, x) + 1];
      phi_[x] = colour_field(rr, bb, s_.tp.phase_field);
    }
  }

  // Interpolated bounce-back (Bouzidi, Firdaouss & Lallemand 2001, linear):
  // population q entering fluid cell x from a solid whose surface lies at
  // `delta` of the link from x's centre (r, b: on entry the half-way values
  // f*_opp(q)(x)), from the post-collision populations of x and, where delta <
  // 1/2, of the next cell away from the solid (half-way where that cell is not
  // fluid). With fluid.lbm.bounce_back: central, Ginzburg, Verhaeghe &
  // d'Humieres' (2008) central linear interpolation from the same three
  // populations at every delta: f*_opp(q)(x) + (1 - 2 delta) / (1 + 2 delta)
  // (f*_opp(q)(x + e_q) - f*_q(x)) (half-way where x + e_q is not fluid).
  // Returns the momentum exchange's share, (out + in) / 2 - w_q.
  // The interpolation does not return what left (half-way bounce-back does):
  // what it falls short of the half-way values, colour by colour, is added to
  // `kept`, which the caller adds to the cell's rest population once all links
  // are pulled; that keeps each colour's mass and carries no momentum.
  double interpolate(const double* f, long x, int q, double delta, double& r, double& b, double* kept) const {
    const double out = r + b;
    kept[0] += r, kept[1] += b;
    if (s_.tp.central) {  // fluid.lbm.bounce_back: central
      if (const long ahead = x + off_[q]; !solid_[ahead] && !open_[ahead]) {
        const double k = (1.0 - 2.0 * delta) / (1.0 + 2.0 * delta);
        r += k * (f[at(L::opp[q], ahead)] - f[at(q, x)]);
        b += k * (f[at(L::opp[q], ahead) + 1] - f[at(q, x) + 1]);
      }
    } else if (delta >= 0.5) {
      const double w = 0.5 / delta;
      r = w * r + (1.0 - w) * f[at(q, x)];
      b = w * b + (1.0 - w) * f[at(q, x) + 1];
    } else if (const long ahead = x + off_[q]; !solid_[ahead] && !open_[ahead]) {
      r = 2.0 * delta * r + (1.0 - 2.0 * delta) * f[at(L::opp[q], ahead)];
      b = 2.0 * delta * b + (1.0 - 2.0 * delta) * f[at(L::opp[q], ahead) + 1];
    }
    kept[0] -= r, kept[1] -= b;
    return 0.5 * (out + r + b) - L::w[q];
  }
  // The red share of a closure's populations where the cell's known ones sum
  // to nothing: even with two fluids, all red with one (no blue of round-off).
  double fallback_red() const {
    return s_.tp.on ? 0.5 : 1.0;
  }
  // The fraction of link q (towards x - e_q) of cell x where it enters an
  // interior solid, or < 0: half-way (no such link, or bounce_back halfway).
  double link_delta(long x, int q) const {
    const int l = link_index_.empty() ? -1 : link_index_[x];
    return l < 0 ? -1.0 : link_delta_[static_cast<std::size_t>(l + q)];
  }

  // The unknown populations of a cell on open faces, as lbm-reference does:
  // outflow faces first (each colour copied from the next cell in, post-
  // collision), then the Zou-He or regularized closure of the colours' sum on
  // pressure and velocity faces, in face order (fluid/lbm/boundaries.hpp).
  // What the closure sets takes the face's phase where it gives one, else the
  // colour fraction of the cell's known populations; the populations a
  // regularized face rebuilds keep their own colour fractions.
  void close_cell(long i, long j, long k, long x, bool* unknown) {
    double r[L::Q], b[L::Q], f[L::Q], F[3];
    for (int q = 0; q < L::Q; ++q) r[q] = pop_.next[at(q, x)], b[q] = pop_.next[at(q, x) + 1];
    const long loc[3] = {lay_.origin[0] + i, lay_.origin[1] + j, lay_.origin[2] + k};
    drive((k * lay_.extent[1] + j) * lay_.extent[0] + i, F);  // this step's forcing comes after
    const auto on = [&](int face) {
      const int axis = face / 2;
      return s_.cells[axis] > 1 && loc[axis] == (face % 2 == 0 ? 0 : s_.cells[axis] - 1);
    };
    const auto inner = [&](int face) {
      const int axis = face / 2, s = face % 2 == 0 ? 1 : -1;
      return x + s * (axis == 0 ? 1 : axis == 1 ? lay_.padded[0] : lay_.padded[0] * lay_.padded[1]);
    };
    for (int face = 0; face < 6; ++face) {
      if (s_.faces[face].type != FaceType::outflow || !on(face)) continue;
      const int axis = face / 2, s = face % 2 == 0 ? 1 : -1;
      for (int q = 0; q < L::Q; ++q)
        if (s * L::e[q][axis] > 0) {
          r[q] = pop_.f[at(q, inner(face))], b[q] = pop_.f[at(q, inner(face)) + 1];
          unknown[q] = false;
        }
    }
    double psi = -1.0, known_r = 0.0, known = 0.0;
    for (int q = 0; q < L::Q; ++q)
      if (!unknown[q]) known_r += r[q], known += r[q] + b[q];
    bool set[L::Q] = {}, rebuilt = false;
    for (int q = 0; q < L::Q; ++q) f[q] = r[q] + b[q] - L::w[q];
    if (close_corner(x, loc, on, f, F, set, known > 0.0 ? known_r / known : fallback_red(), r, b)) return;
    for (int face = 0; face < 6; ++face) {
      const Face& fc = s_.faces[face];
      if ((fc.type != FaceType::pressure && fc.type != FaceType::velocity) || !on(face)) continue;
      const int axis = face / 2, s = face % 2 == 0 ? 1 : -1;
      if (fc.phase_given) psi = 0.5 * (1.0 + fc.phase);
      double ug[3] = {0.0, 0.0, 0.0};
      if (fc.type == FaceType::velocity) fc.velocity(loc, axis, ug);
      if (fc.regularized) {
        double uin[3], rho_in = 0.0, m[3] = {0.0, 0.0, 0.0};
        for (int q = 0; q < L::Q; ++q) {
          const double v = pop_.f[at(q, inner(face))] + pop_.f[at(q, inner(face)) + 1];
          rho_in += v;
          for (int d = 0; d < 3; ++d) m[d] += L::e[q][d] * v;
        }
        for (int d = 0; d < 3; ++d) uin[d] = (m[d] - 0.5 * F[d]) / (Incompressible ? 1.0 : rho_in);
        regularized<L, Incompressible>(f, axis, s, fc.type == FaceType::velocity, fc.rho, ug, uin, F);
        rebuilt = true;
      } else {
        zou_he<L, Incompressible>(f, axis, s, fc.type == FaceType::velocity, fc.rho, ug, F);
      }
      for (int q = 0; q < L::Q; ++q) set[q] = set[q] || s * L::e[q][axis] > 0;
    }
    if (psi < 0.0) psi = known > 0.0 ? known_r / known : fallback_red();
    for (int q = 0; q < L::Q; ++q) {
      const double total = f[q] + L::w[q];
      const double red = set[q] ? psi * total : rebuilt ? share_red(total, r[q], b[q]) : r[q];
      pop_.next[at(q, x)] = set[q] || rebuilt ? red : r[q];
      pop_.next[at(q, x) + 1] = set[q] || rebuilt ? total - red : b[q];
    }
  }

  // A cell where two or three pressure or velocity faces meet: rebuilt whole
  // (boundaries.hpp, rebuild_corner) from the colours' sums, the stress
  // with the relaxation time of the known populations' colour fraction. A population entering through the
  // faces takes the phase of the first of them (face order) that gives one,
  // else the colour fraction of the cell's known populations (psi_known); the
  // rebuilt known ones keep their own fractions. Returns false elsewhere.
  template <class On>
  bool close_corner(long x, const long* loc, On on, double* f, const double* F, bool* set, double psi_known,
                    const double* r, const double* b) {
    bool meets[6];
    int meeting = 0;
    for (int face = 0; face < 6; ++face) {
      const FaceType t = s_.faces[face].type;
      meets[face] = on(face) && (t == FaceType::pressure || t == FaceType::velocity);
      meeting += meets[face];
    }
    if (meeting < 2) return false;
    const long step[3] = {1, lay_.padded[0], lay_.padded[0] * lay_.padded[1]};
    // the stress with the relaxation time of the node's known colour fraction
    const double tau = mixed_tau(2.0 * psi_known - 1.0, colour_.tau_red, colour_.tau_blue);
    rebuild_corner<L, Incompressible>(f, loc, meets, s_.faces, F, tau, [&](const long d[3], double* u) {
      const long c = x + d[0] * step[0] + d[1] * step[1] + d[2] * step[2];
      double rho = 0.0, m[3] = {0.0, 0.0, 0.0};
      for (int q = 0; q < L::Q; ++q) {
        const double v = pop_.f[at(q, c)] + pop_.f[at(q, c) + 1];
        rho += v;
        for (int a = 0; a < 3; ++a) m[a] += L::e[q][a] * v;
      }
      for (int a = 0; a < 3; ++a) u[a] = (m[a] - 0.5 * F[a]) / (Incompressible ? 1.0 : rho);
      return rho;
    });
    for (int q = 0; q < L::Q; ++q) {
      set[q] = corner_unknown<L>(meets, q);
      double psi = psi_known;
      for (int face = 5; face >= 0; --face)
        if (meets[face] && s_.faces[face].phase_given && (face % 2 == 0 ? 1 : -1) * L::e[q][face / 2] > 0)
          psi = 0.5 * (1.0 + s_.faces[face].phase);
      const double total = f[q] + L::w[q];
      const double red = set[q] ? psi * total : share_red(total, r[q], b[q]);
      pop_.next[at(q, x)] = red;
      pop_.next[at(q, x) + 1] = total - red;
    }
    return true;
  }

  // Ladd's momentum exchange: population opp(q) went into the wall and came
  // back as q; the wall took 2 f e_opp(q). The face it is credited to: the
  // first wall face the link crosses (a diagonal link also crosses periodic
  // or open faces); -1 where q is unknown to an open face at this cell (where
  // a wall meets an inlet or outlet), as lbm's fill_walls: the face's
  // condition sets it.
  int wall_face(long i, long j, long k, int q) const {
    const long cell[3] = {lay_.origin[0] + i, lay_.origin[1] + j, lay_.origin[2] + k};
    for (int face = 0; face < 6; ++face) {
      const int axis = face / 2, s = face % 2 == 0 ? 1 : -1;
      const FaceType t = s_.faces[face].type;
      const bool open = t == FaceType::pressure || t == FaceType::velocity || t == FaceType::outflow;
      if (open && s_.cells[axis] > 1 && cell[axis] == (s > 0 ? 0 : s_.cells[axis] - 1) &&
          s * L::e[q][axis] > 0)
        return -1;
    }
    const long loc[3] = {cell[0] - L::e[q][0], cell[1] - L::e[q][1], cell[2] - L::e[q][2]};
    for (int d = 0; d < 3; ++d) {
      if (loc[d] >= 0 && loc[d] < s_.cells[d]) continue;
      const int face = 2 * d + (loc[d] < 0 ? 0 : 1);
      if (s_.faces[face].type == FaceType::wall)
        return face;  // else a periodic or open axis: the wall is another
    }
    return -1;
  }

  // The wall tally's slots of each owned fluid cell (wall_tally.hpp): the
  // wall faces its links are credited to (wall_face), 6 + n - 1 for each
  // interior solid n it borders.
  void build_tally() {
    const int solids = static_cast<int>(s_.tp.solid_phase.size()) - 1;
    tally_.build(owned_cells(), 6 + std::max(solids, 0), [&](long c, std::vector<int>& out) {
      const long i = c % lay_.extent[0], j = (c / lay_.extent[0]) % lay_.extent[1],
                 k = c / (lay_.extent[0] * lay_.extent[1]);
      const long x = lay_.idx(i, j, k);
      if (solid_[x]) return;
      for (int q = 0; q < L::Q; ++q) {
        const long src = x - off_[q];
        if (!solid_[src]) continue;
        const int slot = solid_[src] == kWall ? wall_face(i, j, k, q) : 5 + solid_[src];
        if (slot >= 0 && std::find(out.begin(), out.end(), slot) == out.end()) out.push_back(slot);
      }
    });
  }

  // The colour gradient of eq. 2.56 at fluid cell x; with geometric wetting,
  // next to solids, from the fluid neighbours alone, then turned to the
  // contact angle.
  void gradient(long x, double g[3]) const {
    g[0] = g[1] = g[2] = 0.0;
    const int grain = grain_wet_.empty() ? -1 : grain_wet_index_[x];
    if (grain >= 0) {
      shared_gradient<L>(phi_.data(), [&](long n) { return solid_[n] ? 1.0 : eps_[n]; }, off_, x, g);
      wet_gradient(g, grain_wet_[grain].ns, grain_wet_[grain].cos_theta);
      return;
    }
    const int wet = wet_index_.empty() ? -1 : wet_index_[x];
    if (wet < 0) {
      for (int q = 1; q < L::Q; ++q)
        for (int d = 0; d < 3; ++d) g[d] += L::e[q][d] * phi_[x + off_[q]];
    } else {
      fluid_gradient<L>(phi_.data(), solid_.data(), off_, x, g);
      wet_gradient(g, wet_[wet].ns, wet_[wet].cos_theta);
    }
  }

  // The seed's wetting (geometric wetting turns the gradient instead): grains
  // colour the cells they cover ("Molhabilidade", by solid fraction): phi <- (1 - eps) phi + eps rho
  // cos(theta), so that a wholly covered cell is a solid of colour cos(theta) to its neighbours' colour
  // gradient while a cut cell keeps its fluid's share. (The phase field takes eps cos(theta): it has no
  // density in it.)
  void colour_grains() {
    if (s_.tp.geometric) return;
    for (const Grain& m : grains_) {
      double rho = 0.0;
      for (int q = 0; q < L::Q; ++q) rho += pop_.next[at(q, m.x)] + pop_.next[at(q, m.x) + 1];
      if (s_.tp.phase_field) rho = 1.0;
      phi_[m.x] = (1.0 - m.eps) * phi_[m.x] + m.eps * rho * m.wetting;
    }
  }

  // Four neighbouring cells off the plain path (next to solids or open faces,
  // wetted), already streamed into `next`: collide_cell's colour gradient and
  // force of each fluid one, then its collision on four lanes (the same bits
  // per cell: the lanes are independent and the file has no fused
  // multiply-adds). Solid and grain cells ride along at rest and are not
  // stored. False, touching nothing, where fewer than two are fluid or their
  // forces differ.
  bool collide4_cells(long i, long j, long k, long x) {
    const long c = (k * lay_.extent[1] + j) * lay_.extent[0] + i;
    bool fluid[4];
    double F[3], Fm[3], g[3][4] = {}, is_fluid[4];  // g: none in one colour (red_collide_lanes reads none)
    int count = 0;
    for (int m = 0; m < 4; ++m) {
      fluid[m] = !solid_[x + m] && !grain_[x + m];
      is_fluid[m] = fluid[m] ? 1.0 : 0.0;
      if (!fluid[m]) continue;
      force(c + m, count == 0 ? F : Fm);
      if (count++ > 0 && std::memcmp(Fm, F, sizeof F) != 0) return false;  // the same bits, -0 included
    }
    if (count < 2) return false;
    for (int m = 0; m < 4 && !one_colour_; ++m) {
      double gm[3] = {0.0, 0.0, 0.0};
      if (fluid[m]) gradient(x + m, gm);
      for (int d = 0; d < 3; ++d) g[d][m] = gm[d];
    }
    const long n = cells_;
    double* next = pop_.next.data();
    const Vec4 zero = splat<Vec4>(0.0);
    const auto keep = swap_middle(Vec4{is_fluid[0], is_fluid[1], is_fluid[2], is_fluid[3]}) > zero;
    Vec4 r[L::Q], b[L::Q], gl[3];
    for (int d = 0; d < 3; ++d) gl[d] = swap_middle(Vec4{g[d][0], g[d][1], g[d][2], g[d][3]});
    for (int q = 0; q < L::Q; ++q) {
      split_pairs(detail::get(next + 2 * (q * n + x)), detail::get(next + 2 * (q * n + x) + 4), r[q], b[q]);
      r[q] = keep ? r[q] : splat<Vec4>(L::w[q]);
      b[q] = keep ? b[q] : zero;
    }
    const Vec4 uu = one_colour_ ? red_collide_lanes<L, Incompressible, Vec4>(r, colour_, F)
                                : colour_collide_lanes<L, Incompressible, Vec4>(r, b, gl, colour_, F);
    const Vec4 uu_cells = swap_middle(uu);
    for (int m = 0; m < 4; ++m)
      if (fluid[m]) max_u2_ = nan_max(max_u2_, uu_cells[m]);
    for (int q = 0; q < L::Q; ++q) {
      Vec4 lo, hi;
      join_pairs(r[q], one_colour_ ? zero : b[q], lo, hi);  // cells 0 1 in lo, 2 3 in hi
      double* p = next + 2 * (q * n + x);
      for (int m = 0; m < 4; ++m)
        if (fluid[m])
          p[2 * m] = (m < 2 ? lo : hi)[2 * (m % 2)], p[2 * m + 1] = (m < 2 ? lo : hi)[2 * (m % 2) + 1];
    }
    return true;
  }

  void collide_cell(long i, long j, long k, long x) {
    double g[3], r[L::Q], b[L::Q], F[3];
    force((k * lay_.extent[1] + j) * lay_.extent[0] + i, F);
    if (one_colour_) {  // as collide4<true, false>: blue stays +0
      for (int q = 0; q < L::Q; ++q) r[q] = pop_.next[at(q, x)];
      max_u2_ = nan_max(max_u2_, red_collide_lanes<L, Incompressible, double>(r, colour_, F));
      for (int q = 0; q < L::Q; ++q) pop_.next[at(q, x)] = r[q], pop_.next[at(q, x) + 1] = 0.0;
      return;
    }
    gradient(x, g);
    for (int q = 0; q < L::Q; ++q) r[q] = pop_.next[at(q, x)], b[q] = pop_.next[at(q, x) + 1];
    const double uu = colour_collide<L, Incompressible>(r, b, g, colour_, F);
    max_u2_ = nan_max(max_u2_, uu);
    for (int q = 0; q < L::Q; ++q) pop_.next[at(q, x)] = r[q], pop_.next[at(q, x) + 1] = b[q];
  }

  const Setup& s_;
  Decomposition dec_;
  grid::GhostExchange ghosts_;  // of the colour field
  ColourParams colour_;
  Layout lay_;
  long cells_ = 0;  // of the block with its ghosts
  long off_[L::Q];
  // Red and blue side by side: red population q of cell x at at(q, x), blue
  // right after it (one stream per velocity for both colours).
  Populations<L, 2> pop_;
  std::vector<double> phi_;          // rho_r - rho_b of the pulled populations (two fluids); solids: their colour
  std::vector<std::uint8_t> solid_;  // 0 fluid, solid id, or kWall
  struct Wet {
    double ns[3];
    double cos_theta;
  };
  std::vector<std::uint8_t> open_;  // 1: a ghost beyond a pressure, velocity or outflow face
  struct OpenGhost {
    long x, source;  // the ghost; the face's cell whose colour it copies (-1: phase)
    double phase;
  };
  std::vector<OpenGhost> open_ghosts_;
  std::vector<int> wet_index_;  // geometric wetting: per cell, into wet_ (-1: no solid neighbour)
  // Interpolated bounce-back: per cell, where its L::Q link fractions start in
  // link_delta_ (-1: no link into an interior solid; empty: half-way); a
  // fraction < 0: no such link.
  std::vector<int> link_index_;
  std::vector<double> link_delta_;
  std::vector<Wet> wet_;
  std::vector<double> src_;
  std::function<void()> hook_;                // immersed boundaries: runs between streaming and collision
  // One fluid with interior solids: blue is +0 everywhere and there is no
  // surface tension (the two-fluid arithmetic leaves it so to the bit).
  bool one_colour_ = !s_.tp.on;
  bool fused_ = true;  // neither a source nor a hook: plain cells take the fused four-cell passes
  std::vector<double> cell_force_;            // their force, 3 per owned cell (lattice units)
  std::vector<long> forced_;                  // the owned cells cell_force_ holds forces on
  std::vector<std::uint8_t> forced_cell_;     // the same per cell of the block (1: forced)
  std::vector<std::uint8_t> plain_pull_;      // 1: a fluid cell whose neighbours are all fluid
  std::vector<std::uint8_t> static_special_;  // 1: a solid, or a fluid cell with wetting (walls, solids)
  std::vector<std::uint8_t> special_;         // the same, and the cells grains wet
  struct Grain {  // a partially saturated cell
    long x;
    double eps, wetting;  // solid fraction, cos(theta)
  };
  std::vector<Grain> grains_;
  std::vector<long> grain_cells_;    // their owned-cell indices, as set_psm got them
  std::vector<std::uint8_t> grain_;  // per cell: 1 in grains_ (collided by psm() only)
  std::vector<double> eps_, grain_cos_;  // geometric wetting: per cell of the block and ghosts
  std::vector<int> grain_wet_index_;     // per cell, into grain_wet_ (-1: no grain in or next to it)
  std::vector<long> grain_set_, grain_touched_;  // cells whose eps_ was set; owned cells looked at
  std::vector<std::uint8_t> owned_, touched_;    // per cell: owned; in grain_touched_ (while building it)
  std::vector<long> ghost_cells_;
  std::vector<Wet> grain_wet_;
  double max_u2_ = 0.0;
  lbm::WallTally tally_;  // the walls' and solids' momentum of the window, per fluid cell, lattice units
};

template <class L>
std::unique_ptr<LbmCore> make(const Setup& s, const Decomposition& d, int rank, MPI_Comm comm) {
  if (s.incompressible) return std::make_unique<TwoPhaseCore<L, true>>(s, d, rank, comm);
  return std::make_unique<TwoPhaseCore<L, false>>(s, d, rank, comm);
}

}  // namespace

std::unique_ptr<LbmCore> make_two_phase_core(const Setup& s, const Decomposition& dec, int rank,
                                             MPI_Comm comm) {
  return s.d3 ? make<D3Q19>(s, dec, rank, comm) : make<D2Q9>(s, dec, rank, comm);
}

}  // namespace coflow::fluid::lbm
