#include "fluid/lbm/lbm_solver.hpp"

#include <algorithm>
#if defined(__AVX__)
#include <immintrin.h>
#endif
#include <cmath>
#include <new>
#include <stdexcept>

#include <fmt/format.h>

#include "coflow/log.hpp"
#include "coflow/memory.hpp"
#include "coflow/session.hpp"
#include "coflow/trace.hpp"
#include "coflow/wait.hpp"
#include "fluid/grid/cell_fields.hpp"
#include "fluid/params.hpp"
#include "fluid/lbm/boundaries.hpp"
#include "fluid/lbm/collision.hpp"
#include "fluid/lbm/layout.hpp"
#include "fluid/lbm/populations.hpp"
#include "fluid/lbm/psm_kernel.hpp"
#include "fluid/lbm/phase_series.hpp"
#include "fluid/lbm/two_phase_core.hpp"

namespace coflow::fluid {

using coupler::Box;
using coupler::Decomposition;
using coupler::Index3;
using lbm::FaceType;

namespace {

// Some cells of a block marked: a flag per cell and per row (j, k), so that a
// row without any is passed over at once, and the list that clears them.
struct CellMask {
  std::vector<char> cell, row;
  std::vector<long> cells;
  bool row_marked(long r) const { return !row.empty() && row[static_cast<std::size_t>(r)]; }
  // Marks `list` (x fastest, rows of nx cells, `volume` cells in all) in place of the last one.
  void mark(std::span<const long> list, long nx, long volume) {
    if (cell.empty()) {
      cell.assign(static_cast<std::size_t>(volume), 0);
      row.assign(static_cast<std::size_t>(volume / nx), 0);
    }
    for (long c : cells) cell[static_cast<std::size_t>(c)] = 0, row[static_cast<std::size_t>(c / nx)] = 0;
    cells.assign(list.begin(), list.end());
    for (long c : cells) cell[static_cast<std::size_t>(c)] = 1, row[static_cast<std::size_t>(c / nx)] = 1;
  }
};

template <class L, bool Incompressible>
class Core final : public LbmCore {
 public:
  Core(const lbm::Setup& s, const Decomposition& dec, int rank, MPI_Comm comm)
      : s_(s), dec_(dec), comm_(comm), collision_(lbm::collision_params(s.tau, s.trt, s.magic)) {
    const Box& b = dec.block(rank);
    for (int d = 0; d < 3; ++d) {
      lay_.origin[d] = b.lo[d];
      lay_.extent[d] = b.extent(d);
      lay_.ghost[d] = s.cells[d] > 1 ? 1 : 0;
      lay_.padded[d] = lay_.extent[d] + 2 * lay_.ghost[d];
    }
    // Open faces (pressure, velocity, outflow) of the domain that bound this block.
    for (int f = 0; f < 6; ++f) {
      const int axis = f / 2;
      const bool at_face = f % 2 == 0 ? b.lo[axis] == 0 : b.hi[axis] == s.cells[axis];
      const FaceType t = s.faces[f].type;
      open_[f] = at_face && (t == FaceType::pressure || t == FaceType::velocity || t == FaceType::outflow);
      wall_[f] = at_face && t == FaceType::wall;
    }
    pop_.halo.build(lay_, dec_, rank, comm_);
    build_tally();
    x_local_ = pop_.halo.x_local();
    // The interior pass's rows: whole rows when no other rank borders the block
    // along x (its x ghosts are then ready before the pass), less the cells on
    // open faces; otherwise without the two end cells.
    row_i0_ = x_local_ ? (open_[0] ? 1 : 0) : lay_.ghost[0];
    row_i1_ = x_local_ ? lay_.extent[0] - (open_[1] ? 1 : 0) : lay_.extent[0] - lay_.ghost[0];
    // Rows padded to whole cache lines, and an offset that puts the first cell
    // of those rows on a 64-byte boundary, so that chunks of 8 cells can be
    // written with streaming (non-temporal) stores.
    lay_.padded[0] = (lay_.padded[0] + 7) / 8 * 8;
    lay_.shift = (8 - (lay_.ghost[0] + row_i0_) % 8) % 8;
    // Populations spaced_stride apart when the block fits (the line kernels
    // then keep every address in a register: lbm::SpacedRef), else packed.
    // The spaced arrays reserve 2 Q spaced_stride values of address space;
    // where that is refused (a limit on it), packed.
    const long cells = (lay_.padded[0] * lay_.padded[1] * lay_.padded[2] + lay_.shift + 7) / 8 * 8;
    for (int q = 0; q < L::Q; ++q) off_[q] = lay_.offset(L::e[q]);
    const auto allocate = [&](long stride) {
      pop_.allocate(stride, cells);
      lay_.stride = stride;
    };
    spaced_ = !s.packed && cells <= lbm::spaced_stride;
    try {
      allocate(spaced_ ? lbm::spaced_stride : cells);
    } catch (const std::bad_alloc&) {
      if (!spaced_) throw;
      spaced_ = false;
      log::warn("lbm: no address space for the spaced population layout ({:.1f} GiB); packed layout (slower)",
                2.0 * L::Q * lbm::spaced_stride * sizeof(double) / (1 << 30));
      allocate(cells);
    }
    log::info("lbm: {} population layout", spaced_ ? "spaced" : "packed");
    lean_ = !s.trt && s.force[0] == 0.0 && s.force[1] == 0.0 && s.force[2] == 0.0;
    for (long k = 0; k < lay_.extent[2]; ++k)
      for (long j = 0; j < lay_.extent[1]; ++j)
        for (long i = 0; i < lay_.extent[0]; ++i) {
          double rho, u[3];
          s.initial(lay_.origin[0] + i, lay_.origin[1] + j, lay_.origin[2] + k, rho, u);
          // Stored populations are post-collision, their momentum rho u + F/2
          // (Guo): the body force's half is added, so that u is the one given.
          for (int q = 0; q < L::Q; ++q)
            pop_.f[q * lay_.stride + idx(i, j, k)] =
                lbm::equilibrium<L, Incompressible>(q, rho, u) + lbm::half_force<L>(q, s.force.data());
        }
  }

  void step() override {
    // 1. Start the halo exchange of the post-collision populations; halos with
    //    this rank itself (a periodic axis not split) are copied at once.
    pop_.halo.post(pop_.f.data(), lay_.stride);
    if (hook_) {
      // Immersed boundaries: every ghost first, then the hook (the forcing
      // reads the streamed populations and sets its cells' forces). The
      // forcing runs before the open faces' closures here (after them in the
      // two-fluid core and lbm-reference); no forced cell lies on an open
      // face, since validate keeps bodies the kernel's support and a cell
      // inside every face that is not periodic (immersed/ibm/params.cpp).
      pop_.halo.finish(pop_.f.data(), lay_.stride);
      fill_walls(0, 6);
      hook_();
    } else if (x_local_) {
      // When no other rank borders this block along x, its x ghosts are ready
      // now (copied, or walls filled from owned cells): the interior pass then
      // takes whole rows, and the rows' end cells need no second visit.
      fill_walls(0, 2);
    }
    // 2. Interior rows read no ghost from another rank: compute them while
    //    messages fly.
    max_u2_ = 0.0;
    short_n_ = 0;
    const long i0 = row_i0_, i1 = row_i1_;
    for (long k = lay_.ghost[2]; k < lay_.extent[2] - lay_.ghost[2]; ++k)
      for (long j = lay_.ghost[1]; j < lay_.extent[1] - lay_.ghost[1]; ++j) fast_row(i0, i1, j, k);
    // 3. Ghosts: from neighbours, then walls (bounce-back, seed 000 eq. 2.44).
    if (!hook_) {
      pop_.halo.finish(pop_.f.data(), lay_.stride);
      fill_walls(x_local_ ? 2 : 0, 6);
    }
    // 4. The shell: rows on the block's faces, and the end cells of the others
    //    that the interior pass left.
    for (long k = 0; k < lay_.extent[2]; ++k)
      for (long j = 0; j < lay_.extent[1]; ++j) {
        const bool face_row = (lay_.ghost[1] && (j == 0 || j == lay_.extent[1] - 1)) || (lay_.ghost[2] && (k == 0 || k == lay_.extent[2] - 1));
        if (face_row) {
          shell_row(0, lay_.extent[0], j, k);
          continue;
        }
        if (i0 > 0) shell_row(0, 1, j, k);
        if (i1 < lay_.extent[0] && lay_.extent[0] > 1) shell_row(lay_.extent[0] - 1, lay_.extent[0], j, k);
      }
    short_flush();
#if defined(__AVX__)
    _mm_sfence();  // order the streaming stores before anything reads them
#endif
    pop_.swap();
  }

  void set_hook(std::function<void()> hook) override { hook_ = std::move(hook); }

  void streamed_velocity(std::span<const long> cells, std::span<double> u, std::span<double> rho) const override {
    const long nx = lay_.extent[0], ny = lay_.extent[1];
    for (std::size_t n = 0; n < cells.size(); ++n) {
      const long c = cells[n], i = c % nx, j = (c / nx) % ny, k = c / (nx * ny), x = idx(i, j, k);
      double r = 0, m[3] = {0, 0, 0}, F[3];
      for (int q = 0; q < L::Q; ++q) {
        const double f = pop_.f[q * lay_.stride + x - off_[q]];
        r += f;
        for (int d = 0; d < 3; ++d) m[d] += L::e[q][d] * f;
      }
      drive_at(i, j, k, F);
      const double rho_m = Incompressible ? 1.0 : 1.0 + r;
      for (int d = 0; d < 3; ++d) u[3 * n + d] = (m[d] + 0.5 * F[d]) / rho_m;
      rho[n] = rho_m;
    }
  }

  void set_cell_forces(std::span<const long> cells, std::span<const double> force) override {
    const long nx = lay_.extent[0], volume = nx * lay_.extent[1] * lay_.extent[2];
    if (extra_.empty()) extra_.assign(static_cast<std::size_t>(3 * volume), 0.0);
    for (long c : forced_.cells)
      for (int d = 0; d < 3; ++d) extra_[static_cast<std::size_t>(3 * c + d)] = 0.0;
    forced_.mark(cells, nx, volume);
    for (std::size_t n = 0; n < cells.size(); ++n)
      for (int d = 0; d < 3; ++d) extra_[static_cast<std::size_t>(3 * cells[n] + d)] = force[3 * n + d];
  }

  void macroscopic(std::vector<double>& u, std::vector<double>& rho) const override {
    const long cells = lay_.extent[0] * lay_.extent[1] * lay_.extent[2];
    u.resize(3 * cells);
    rho.resize(cells);
    long c = 0;
    for (long k = 0; k < lay_.extent[2]; ++k)
      for (long j = 0; j < lay_.extent[1]; ++j)
        for (long i = 0; i < lay_.extent[0]; ++i, ++c) {
          const long x = idx(i, j, k);
          double r = 0, jx = 0, jy = 0, jz = 0;
          for (int q = 0; q < L::Q; ++q) {
            const double f = pop_.f[q * lay_.stride + x];
            r += f;
            jx += L::e[q][0] * f;
            jy += L::e[q][1] * f;
            jz += L::e[q][2] * f;
          }
          // Post-collision momentum carries the whole force: u = (j - F/2) / rho_m
          // for the body force. A point-particle source is an impulse the
          // particles gave up in the window: it counts in full, so that fluid +
          // particles balance at the window's end.
          const double rho_m = Incompressible ? 1.0 : 1.0 + r;  // r: sum of the zero-centred populations
          // An immersed boundary's force is a body force too (Guo): half of it out.
          const double* e = extra_.empty() ? nullptr : &extra_[static_cast<std::size_t>(3 * c)];
          u[3 * c + 0] = (jx - 0.5 * (s_.force[0] + (e ? e[0] : 0.0))) / rho_m;
          u[3 * c + 1] = (jy - 0.5 * (s_.force[1] + (e ? e[1] : 0.0))) / rho_m;
          u[3 * c + 2] = (jz - 0.5 * (s_.force[2] + (e ? e[2] : 0.0))) / rho_m;
          rho[c] = 1.0 + r;
        }
  }

  double max_u2() const override { return max_u2_; }
  void set_max_u2(double u2) override {
    max_u2_ = u2;
  }
  int q() const override { return L::Q; }

  void get_populations(std::vector<double>& out) const override {
    out.resize(static_cast<std::size_t>(lay_.extent[0] * lay_.extent[1] * lay_.extent[2]) * L::Q);
    std::size_t o = 0;
    for (long k = 0; k < lay_.extent[2]; ++k)
      for (long j = 0; j < lay_.extent[1]; ++j)
        for (long i = 0; i < lay_.extent[0]; ++i)
          for (int q = 0; q < L::Q; ++q) out[o++] = pop_.f[q * lay_.stride + idx(i, j, k)];
  }
  std::vector<double> stored_offset() const override {
    return {L::w, L::w + L::Q};
  }
  void set_populations(const std::vector<double>& in) override {
    std::size_t o = 0;
    for (long k = 0; k < lay_.extent[2]; ++k)
      for (long j = 0; j < lay_.extent[1]; ++j)
        for (long i = 0; i < lay_.extent[0]; ++i)
          for (int q = 0; q < L::Q; ++q) pop_.f[q * lay_.stride + idx(i, j, k)] = in[o++];
  }

  // The partially saturated cells of the next steps: the step leaves them to
  // psm(), which collides them once (it would overwrite the step's result).
  void set_psm(std::span<const long> cells, std::span<const double> fraction,
               std::span<const double> wetting) override {
    (void)fraction, (void)wetting;
    psm_.mark(cells, lay_.extent[0], lay_.extent[0] * lay_.extent[1] * lay_.extent[2]);
  }

  // Partially saturated cells (psm_kernel.hpp) on the cells of the step just
  // taken: pull the same streamed populations from the previous array (its
  // ghosts still hold the halo and wall values) and collide them (the step
  // left them, except those on open faces, which psm() leaves). Four
  // cells that follow each other along x in the list (a grain's chord) take
  // one four-lane collision (docs/performance.md: the quickstart's wall fell
  // by about a tenth).
  void psm(std::span<const long> cells, std::span<const double> fraction, std::span<const double> us,
           std::span<double> gain) override {
    for (std::size_t n = 0; n < cells.size();) {
      const long c = cells[n];
      const long i = c % lay_.extent[0], j = (c / lay_.extent[0]) % lay_.extent[1], k = c / (lay_.extent[0] * lay_.extent[1]);
      // Cells on an open face (pressure, velocity, outflow) keep their Zou-He /
      // outflow closure and stay fluid: a grain there is leaving the domain.
      if (on_open_face(i, j, k)) {
        ++n;
        continue;
      }
      // Lanes i + 1 and i + 2 lie inside the row: only i + 3 can be on an open x face.
      const bool four = n + 4 <= cells.size() && i + 3 < lay_.extent[0] && cells[n + 1] == c + 1 &&
                        cells[n + 2] == c + 2 && cells[n + 3] == c + 3 && !on_open_face(i + 3, j, k);
      if (four) {
        psm_lanes(idx(i, j, k), n, fraction, us, gain);
        n += 4;
        continue;
      }
      const long x = idx(i, j, k);
      double f[L::Q], out[L::Q];
      for (int q = 0; q < L::Q; ++q) f[q] = pop_.next[q * lay_.stride + x - off_[q]];
      const double uu =
          lbm::psm_collide<L, Incompressible>(f, s_.force.data(), collision_.omega, collision_.omega_minus,
                                              s_.tau, fraction[n], &us[3 * n], out, &gain[3 * n]);
      max_u2_ = lbm::nan_max(max_u2_, uu);
      for (int q = 0; q < L::Q; ++q) pop_.f[q * lay_.stride + x] = out[q];
      ++n;
    }
  }

  bool on_open_face(long i, long j, long k) const {
    const long loc[3] = {i, j, k};
    for (int f = 0; f < 6; ++f)
      if (open_[f] && loc[f / 2] == (f % 2 == 0 ? 0 : lay_.extent[f / 2] - 1)) return true;
    return false;
  }

  // psm() on the list's cells n .. n + 3, which are x .. x + 3 of one row.
  void psm_lanes(long x, std::size_t n, std::span<const double> fraction, std::span<const double> us,
                 std::span<double> gain) {
    using lbm::Vec4;
    Vec4 f[L::Q], out[L::Q], u[3], g[3] = {};
    for (int q = 0; q < L::Q; ++q) f[q] = lbm::detail::get(&pop_.next[q * lay_.stride + x - off_[q]]);
    for (int d = 0; d < 3; ++d)
      u[d] = Vec4{us[3 * n + d], us[3 * n + 3 + d], us[3 * n + 6 + d], us[3 * n + 9 + d]};
    const Vec4 uu = lbm::psm_collide_lanes<L, Incompressible, Vec4>(
        f, s_.force.data(), collision_.omega, collision_.omega_minus, s_.tau, lbm::detail::get(&fraction[n]),
        u, out, g);
    for (int l = 0; l < 4; ++l) max_u2_ = lbm::nan_max(max_u2_, uu[l]);
    for (int q = 0; q < L::Q; ++q) __builtin_memcpy(&pop_.f[q * lay_.stride + x], &out[q], sizeof(Vec4));
    for (int l = 0; l < 4; ++l)
      for (int d = 0; d < 3; ++d) gain[3 * (n + l) + d] += g[d][l];
  }

  long first_nonfinite() const override {
    long c = 0;
    for (long k = 0; k < lay_.extent[2]; ++k)
      for (long j = 0; j < lay_.extent[1]; ++j)
        for (long i = 0; i < lay_.extent[0]; ++i, ++c)
          for (int q = 0; q < L::Q; ++q)
            if (!std::isfinite(pop_.f[q * lay_.stride + idx(i, j, k)])) return c;
    return -1;
  }

 private:
  long idx(long i, long j, long k) const { return lay_.idx(i, j, k); }

  void set_source(std::span<const double> force) override {
    src_.assign(force.begin(), force.end());
    src_list_.clear();
    for (std::size_t c = 0; c < src_.size() / 3; ++c)
      if (src_[3 * c] != 0.0 || src_[3 * c + 1] != 0.0 || src_[3 * c + 2] != 0.0)
        src_list_.push_back(static_cast<long>(c));
    sourced_.mark(src_list_, lay_.extent[0], static_cast<long>(src_.size() / 3));
  }

  // The drive: body force plus the cell's momentum source.
  void drive_at(long i, long j, long k, double F[3]) const {
    const long c = (k * lay_.extent[1] + j) * lay_.extent[0] + i;
    for (int d = 0; d < 3; ++d) F[d] = s_.force[d] + (src_.empty() ? 0.0 : src_[3 * c + d]);
  }
  // The drive plus the cell's immersed-boundary force.
  void force_at(long i, long j, long k, double F[3]) const {
    drive_at(i, j, k, F);
    if (extra_.empty()) return;
    const long c = (k * lay_.extent[1] + j) * lay_.extent[0] + i;
    for (int d = 0; d < 3; ++d) F[d] += extra_[3 * c + d];
  }

  // Cells with a momentum source or an immersed-boundary force: one at a time, each with its force.
  void source_row(long i0, long i1, long j, long k) {
    for (long i = i0; i < i1; ++i) {
      const long x = idx(i, j, k);
      double f[L::Q], F[3];
      force_at(i, j, k, F);
      for (int q = 0; q < L::Q; ++q) f[q] = pop_.f[q * lay_.stride + x - off_[q]];
      const double uu = lbm::collide<L, Incompressible>(f, collision_, F);
      max_u2_ = lbm::nan_max(max_u2_, uu);
      for (int q = 0; q < L::Q; ++q) pop_.next[q * lay_.stride + x] = f[q];
    }
  }

  // The hot loop: cells of one row that read only valid data. The compiler
  // vectorises over i: each population streams with a constant offset.
  // Partially saturated cells are left to psm(): the runs between them.
  void fast_row(long i0, long i1, long j, long k) {
    if (i1 <= i0) return;
    const long row = k * lay_.extent[1] + j;
    if (!psm_.row_marked(row)) {
      fluid_row(i0, i1, j, k);
      return;
    }
    for_runs(&psm_.cell[static_cast<std::size_t>(row * lay_.extent[0])], i0, i1,
             [&](long a, long b, bool psm) {
               if (!psm) fluid_row(a, b, j, k);
             });
  }

  // The runs [a, b) of [i0, i1) over which mask (a row's) holds one value:
  // run(a, b, mask[a] != 0) for each.
  template <class Run>
  static void for_runs(const char* mask, long i0, long i1, Run&& run) {
    for (long i = i0; i < i1;) {
      long e = i + 1;
      while (e < i1 && mask[e] == mask[i]) ++e;
      run(i, e, mask[i] != 0);
      i = e;
    }
  }

  // Cells [i0, i1) of a row, none partially saturated: those with a momentum
  // source one at a time, each with its force, the runs between them as in
  // any other row (a whole row by the one-cell kernel would give its
  // source-free cells other bits than where the row is cut along x).
  void fluid_row(long i0, long i1, long j, long k) {
    const long row = k * lay_.extent[1] + j;
    if (sourced_.row_marked(row)) {
      for_runs(&sourced_.cell[static_cast<std::size_t>(row * lay_.extent[0])], i0, i1,
               [&](long a, long b, bool sourced) {
                 if (sourced)
                   source_row(a, b, j, k);
                 else
                   sourceless_row(a, b, j, k);
               });
      return;
    }
    sourceless_row(i0, i1, j, k);
  }

  void sourceless_row(long i0, long i1, long j, long k) {
    const long row = k * lay_.extent[1] + j;
    if (forced_.row_marked(row)) {
      forced_row(i0, i1, j, k);
      return;
    }
    plain_row(i0, i1, j, k);
  }

  // BGK without body force takes the lean kernel; the choice is made per row
  // (a test inside the chunk loop halves the speed).
  void plain_row(long i0, long i1, long j, long k) {
    if (lean_)
      vec_row<true>(i0, i1, j, k);
    else
      vec_row<false>(i0, i1, j, k);
  }

  // A row through an immersed body's forcing: its forced cells one at a
  // time, each with its force, the runs between them by the row kernel.
  void forced_row(long i0, long i1, long j, long k) {
    const char* forced = &forced_.cell[static_cast<std::size_t>((k * lay_.extent[1] + j) * lay_.extent[0])];
    for_runs(forced, i0, i1, [&](long a, long b, bool f) {
      if (f)
        source_row(a, b, j, k);
      else
        plain_row(a, b, j, k);
    });
  }

  // Eight cells (one cache line per population) at a time with the lean
  // kernel (BGK without force) or the general one (TRT, Guo forcing); see
  // lbm::bgk_line. Runs shorter than a line: short_row, the same kernel.
  template <bool Lean>
  void vec_row(long i0, long i1, long j, long k) {
    if (spaced_)
      vec_row<Lean>(i0, i1, j, k, lbm::SpacedRef<L>(pop_.f.data(), pop_.next.data(), idx(0, j, k), off_));
    else
      vec_row<Lean>(i0, i1, j, k, lbm::LineRef{pop_.f.data() + idx(0, j, k), pop_.next.data() + idx(0, j, k), lay_.stride, off_});
  }

  template <bool Lean, class Ref>
  void vec_row(long i0, long i1, long j, long k, const Ref ref) {
    using lbm::Vec4;
    const long base = idx(0, j, k);
    if (i1 - i0 < 8) {
      short_row(base + i0, i1 - i0);
      return;
    }
    const auto p = collision_;
    const double F[3] = {s_.force[0], s_.force[1], s_.force[2]};
    Vec4 mx = {0.0, 0.0, 0.0, 0.0};  // max u^2, NaN-sticky
    const auto chunk = [&](long i, bool stream) __attribute__((always_inline)) {
      Vec4 uu;
      if constexpr (Lean)
        uu = stream ? lbm::bgk_line<L, Incompressible, true>(ref, i, p.omega)
                    : lbm::bgk_line<L, Incompressible, false>(ref, i, p.omega);
      else
        uu = stream ? lbm::collide_line<L, Incompressible, true>(ref, i, p, F)
                    : lbm::collide_line<L, Incompressible, false>(ref, i, p, F);
      mx = lbm::nan_max(mx, uu);
    };
    // A cell's update reads only the previous array, so computing it twice
    // writes the same values: a head and a tail that are not whole cache
    // lines take a full chunk that overlaps its neighbour, with cached stores.
    long i = i0, done = i0;  // cells [i0, done) are written
    if (const long mis = (base + i0) & 7; mis != 0) {
      chunk(i0, false);
      i = i0 + 8 - mis;
      done = i0 + 8;
    }
    for (; i + 8 <= i1; i += 8, done = i) chunk(i, true);
    if (done < i1) chunk(i1 - 8, false);
    for (int w = 0; w < 4; ++w) max_u2_ = lbm::nan_max(max_u2_, mx[w]);
  }

  // Runs of fewer than 8 cells (the end cells of rows split across ranks
  // along x, the gaps between partially saturated, forced or sourced cells) take the
  // same line kernel as longer runs, so that a cell's bits do not depend on
  // where its row is cut: their cells are gathered, eight at a time, into one
  // line (short_flush). The lanes are independent, so a cell's result does
  // not depend on the cells beside it in the line. With the one-cell
  // collide(), whose arithmetic differs at round-off from the lean kernel's,
  // [2,1,1] blocks changed the Taylor-Green vortex by 1.1e-15 after 500 steps;
  // with a line of eight per run, the [2,1,1] 128 x 64 x 64 duct computed
  // 15-40 % longer.
  void short_row(long x, long n) {
    for (long l = 0; l < n; ++l) {
      short_x_[short_n_++] = x + l;
      if (short_n_ == 8) short_flush();
    }
  }

  // The gathered cells through the line kernel (the last one repeated to fill
  // the line), their results scattered back. Before the step's end: the
  // gathered cells' results are not written until then.
  void short_flush() {
    if (short_n_ == 0) return;
    const long n = short_n_, N = lay_.stride;
    short_n_ = 0;
    const double* src = pop_.f.data();
    double* dst = pop_.next.data();
    for (int q = 0; q < L::Q; ++q)
      for (long l = 0; l < 8; ++l) short_in_[q * 8 + l] = src[q * N + short_x_[std::min(l, n - 1)] - off_[q]];
    static constexpr long no_offsets[L::Q] = {};
    const lbm::LineRef ref{short_in_, short_out_, 8, no_offsets};
    const double F[3] = {s_.force[0], s_.force[1], s_.force[2]};
    const lbm::Vec4 uu = lean_ ? lbm::bgk_line<L, Incompressible, false>(ref, 0, collision_.omega)
                               : lbm::collide_line<L, Incompressible, false>(ref, 0, collision_, F);
    for (int w = 0; w < 4; ++w) max_u2_ = lbm::nan_max(max_u2_, uu[w]);
    for (int q = 0; q < L::Q; ++q)
      for (long l = 0; l < n; ++l) dst[q * N + short_x_[l]] = short_out_[q * 8 + l];
  }

  // Cells of the shell: runs off the open faces take the row kernels.
  void shell_row(long i0, long i1, long j, long k) {
    long run = i0;  // first cell of the current run of cells off the open faces
    for (long i = i0; i < i1; ++i) {
      const long loc[3] = {i, j, k};
      bool open = false;
      for (int f = 0; f < 6 && !open; ++f)
        open = open_[f] && loc[f / 2] == (f % 2 == 0 ? 0 : lay_.extent[f / 2] - 1);
      if (!open) continue;
      fast_row(run, i, j, k);
      run = i + 1;
      open_cell(i, j, k);
    }
    fast_row(run, i1, j, k);
  }

  // A cell on an open face: pull, close the unknowns (boundaries.hpp), collide.
  // The closure takes the body force and the momentum source (as
  // lbm-reference and the two-phase core do); the collision also this step's
  // immersed-boundary force.
  void open_cell(long i, long j, long k) {
    double F[3], Fc[3];
    force_at(i, j, k, F);
    drive_at(i, j, k, Fc);
    const long x = idx(i, j, k);
    double f[L::Q];
    for (int q = 0; q < L::Q; ++q) f[q] = pop_.f[q * lay_.stride + x - off_[q]];
    lbm::close_open_faces<L, Incompressible>(f, pop_.f.data(), lay_, i, j, k, open_, s_.faces, Fc,
                                             collision_.tau);
    const double uu = lbm::collide<L, Incompressible>(f, collision_, F);
    max_u2_ = lbm::nan_max(max_u2_, uu);
    for (int q = 0; q < L::Q; ++q) pop_.next[q * lay_.stride + x] = f[q];
  }

  // Bounce-back on this block's wall faces [face0, face1) (boundaries.hpp).
  void fill_walls(int face0, int face1) {
    lbm::fill_walls<L>(pop_.f.data(), lay_, off_, wall_, open_, face0, face1, tally_);
  }
  coupler::ExactSums take_wall_momentum(double unit) override {
    return tally_.take(unit);
  }
  // The tally's slots: each owned cell on a wall face's layer, that face.
  void build_tally() {
    tally_.build(lay_.extent[0] * lay_.extent[1] * lay_.extent[2], 6, [&](long c, std::vector<int>& out) {
      const long at[3] = {c % lay_.extent[0], (c / lay_.extent[0]) % lay_.extent[1],
                          c / (lay_.extent[0] * lay_.extent[1])};
      for (int f = 0; f < 6; ++f)
        if (wall_[f] && at[f / 2] == (f % 2 == 0 ? 0 : lay_.extent[f / 2] - 1)) out.push_back(f);
    });
  }

  const lbm::Setup& s_;
  Decomposition dec_;
  MPI_Comm comm_;
  lbm::CollisionParams collision_;
  lbm::Layout lay_;   // where the populations of the block live
  long off_[L::Q];    // streaming offset of population q in cells
  lbm::Populations<L> pop_;  // the populations (f current, next the step's output) and their halo
  bool spaced_ = false;          // lay_.stride = lbm::spaced_stride
  bool lean_ = false;  // BGK without body force: lbm::bgk_line
  // short_row's gathered cells; short_in_ reaches as far as the kernel's
  // prefetch pointers (prefetch_ahead)
  alignas(32) double short_in_[L::Q * 8 + lbm::prefetch_ahead] = {}, short_out_[L::Q * 8] = {};
  long short_x_[8] = {};
  int short_n_ = 0;
  std::vector<double> src_;     // per owned cell source (lattice units), empty: none
  CellMask sourced_;            // cells whose source is not zero
  std::vector<long> src_list_;  // (set_source's list for sourced_)
  // Immersed boundaries: the hook, the forces of this step's forced cells.
  std::function<void()> hook_;
  std::vector<double> extra_;
  CellMask forced_;  // the cells with such a force
  CellMask psm_;     // partially saturated cells (set_psm), collided by psm() only
  double max_u2_ = 0.0;
  lbm::WallTally tally_;  // lattice momentum each wall took since the last take, per cell
  bool open_[6], wall_[6];
  bool x_local_ = false;    // no other rank borders the block along x
  long row_i0_ = 0, row_i1_ = 0;  // cells of the interior pass's rows
};

template <class L>
std::unique_ptr<LbmCore> make_core(const lbm::Setup& s, const Decomposition& d, int rank, MPI_Comm comm) {
  if (s.incompressible) return std::make_unique<Core<L, true>>(s, d, rank, comm);
  return std::make_unique<Core<L, false>>(s, d, rank, comm);
}

}  // namespace

LbmSolver::LbmSolver(const Setup& setup, const Params& p)
    : s_(lbm::make_setup(setup.cfg, setup.params, p, setup.time_step)), cfg_(&setup.cfg), comm_(setup.comm),
      owned_(setup.decomposition.block(setup.rank)) {
  if (s_.tp.on || s_.tp.any_solid())
    core_ = lbm::make_two_phase_core(s_, setup.decomposition, setup.rank, comm_);
  else
    core_ = s_.d3 ? make_core<lbm::D3Q19>(s_, setup.decomposition, setup.rank, comm_)
                  : make_core<lbm::D2Q9>(s_, setup.decomposition, setup.rank, comm_);
  const auto& dims = setup.decomposition.dims();
  if (s_.tp.on)
    log::info("lbm two-phase (colour gradient): surface tension {:.6g} (lattice), beta {}, tau red {} blue {:.6g}",
              s_.tp.gamma, s_.tp.beta, s_.tau, s_.tp.tau_blue);
  log::info("lbm {} {} {}, blocks {}x{}x{}: {}", s_.d3 ? "D3Q19" : "D2Q9", s_.trt ? "TRT" : "BGK",
            s_.incompressible ? "incompressible" : "standard", dims[0], dims[1], dims[2], s_.units.describe());
}

void LbmSolver::advance(double dt) {
  const long n = std::lround(dt / s_.units.dt);
  double u2 = 0.0;
  for (long i = 0; i < n; ++i) {
    lbm::ramp_faces(s_.faces, steps_);  // the core reads the faces through its reference to s_
    core_->step();
    if (!solid_cells_.empty()) {
      core_->psm(solid_cells_, solid_fraction_, solid_us_, solid_gain_);
      ++solid_steps_;
    }
    ++steps_;
    u2 = lbm::nan_max(u2, core_->max_u2());
  }
  // Mach number (seed 000 eq. 2.38 and 2.52): warn above 0.1, stop above 0.3 or on NaN.
  double global = 0.0;
  const double local = (u2 != u2) ? 1e300 : u2;
  MPI_Allreduce(&local, &global, 1, MPI_DOUBLE, MPI_MAX, comm_);
  const double mach = std::sqrt(global / lbm::cs2);
  if (global >= 1e300 || !std::isfinite(mach)) {
    const long c = core_->first_nonfinite();
    std::string where = "on another rank";
    if (c >= 0) {
      const long nx = owned_.extent(0), ny = owned_.extent(1);
      where = fmt::format("in cell ({}, {}, {})", owned_.lo[0] + c % nx, owned_.lo[1] + (c / nx) % ny,
                          owned_.lo[2] + c / (nx * ny));
    }
    throw coupler::SolverError(fmt::format("lbm: the populations are not finite at step {} {} (field: "
                                           "distribution functions); reduce the velocities or the forcing",
                                           steps_, where));
  }
  if (mach > 0.3) {
    // A momentum source that drives the flow by itself gets its own advice: a
    // finer grid would concentrate it further.
    const std::string source = source_diagnosis();
    throw coupler::SolverError(fmt::format(
        "lbm: Mach number {:.3f} at step {} exceeds 0.3 (max velocity {:.4g} m/s {}); the lattice Boltzmann "
        "method is invalid there. {}",
        mach, steps_, std::sqrt(global) * s_.units.velocity(), fastest_cell(),
        source.empty() ? mach_advice(mach) : source));
  }
  if (mach > 0.1 && !mach_warned_) {
    log::warn("lbm: Mach number {:.3f} at step {} exceeds 0.1 (max velocity {:.4g} m/s {}): compressibility errors "
              "grow as Ma^2. {}",
              mach, steps_, std::sqrt(global) * s_.units.velocity(), fastest_cell(), source_diagnosis());
    mach_warned_ = true;
  }
}

// Where the fastest fluid is (collective): "in cell (i, j, k) at (x, y, z) m".
std::string LbmSolver::fastest_cell() const {
  std::vector<double> u, rho;
  core_->macroscopic(u, rho);
  struct {
    double u2;
    int rank;
  } mine{-1.0, 0}, best{};
  MPI_Comm_rank(comm_, &mine.rank);
  long at = -1;
  for (std::size_t c = 0; 3 * c + 2 < u.size(); ++c) {
    const double u2 = u[3 * c] * u[3 * c] + u[3 * c + 1] * u[3 * c + 1] + u[3 * c + 2] * u[3 * c + 2];
    if (u2 > mine.u2) {
      mine.u2 = u2;
      at = static_cast<long>(c);
    }
  }
  MPI_Allreduce(&mine, &best, 1, MPI_DOUBLE_INT, MPI_MAXLOC, comm_);
  long cell[3] = {0, 0, 0};
  if (best.rank == mine.rank && at >= 0) {
    const long nx = owned_.extent(0), ny = owned_.extent(1);
    cell[0] = owned_.lo[0] + at % nx;
    cell[1] = owned_.lo[1] + (at / nx) % ny;
    cell[2] = owned_.lo[2] + at / (nx * ny);
  }
  MPI_Bcast(cell, 3, MPI_LONG, best.rank, comm_);
  const double dx = s_.units.dx;
  return fmt::format("in cell ({}, {}, {}) at ({:.4g}, {:.4g}, {:.4g}) m", cell[0], cell[1], cell[2],
                     s_.lower[0] + (cell[0] + 0.5) * dx, s_.lower[1] + (cell[1] + 0.5) * dx,
                     s_.lower[2] + (cell[2] + 0.5) * dx);
}

// What brings Mach down to 0.1 with the physics kept: at a fixed viscosity and
// grid, dt = (tau - 1/2) dx^2 / (3 nu), so the lattice velocity u dt / dx, and
// Mach, scale with tau - 1/2 (raising tau raises Mach); at a fixed tau they
// scale with dx.
std::string LbmSolver::mach_advice(double mach) const {
  const double f = 0.1 / mach;
  return fmt::format("Mach scales with tau - 1/2 at this viscosity and grid: fluid.lbm.tau = {:.4g} (now {}) "
                     "gives Mach 0.1; or refine the grid to dx = {:.4g} m ({:.0f}x as many cells per axis); or lower "
                     "the velocities",
                     0.5 + (s_.units.tau - 0.5) * f, s_.units.tau, s_.units.dx * f, std::ceil(1.0 / f));
}

// When the point particles' momentum source is what drives the fluid past
// Mach 0.1 (collective): the largest source density f and where it acts, with
// the speed viscosity alone lets it drive across one cell, f dx^2 / mu. Above
// the speed of Mach 0.1 that source by itself makes the flow too fast. The
// usual cause (docs/validation.md, "point particles resting on a wall"):
// particles that settled on a wall fall onto it step after step and hand
// their weight to the cells next to it through drag. "" when no source acts
// or it is too weak to matter.
std::string LbmSolver::source_diagnosis() const {
  struct {
    double f;
    int rank;
  } mine{0.0, 0}, best{};
  MPI_Comm_rank(comm_, &mine.rank);
  long at = -1;
  for (std::size_t c = 0; 3 * c + 2 < source_si_.size(); ++c) {
    const double f = std::hypot(source_si_[3 * c], source_si_[3 * c + 1], source_si_[3 * c + 2]);
    if (f > mine.f) mine.f = f, at = static_cast<long>(c);
  }
  MPI_Allreduce(&mine, &best, 1, MPI_DOUBLE_INT, MPI_MAXLOC, comm_);
  long cell[3] = {-1, -1, -1};
  if (best.rank == mine.rank && at >= 0) {
    const long nx = owned_.extent(0), ny = owned_.extent(1);
    cell[0] = owned_.lo[0] + at % nx, cell[1] = owned_.lo[1] + (at / nx) % ny, cell[2] = owned_.lo[2] + at / (nx * ny);
  }
  MPI_Bcast(cell, 3, MPI_LONG, best.rank, comm_);
  const auto& u = s_.units;
  const double drive = best.f * u.dx * u.dx / (u.rho * u.nu), mach01 = 0.1 * std::sqrt(lbm::cs2) * u.velocity();
  if (cell[0] < 0 || drive <= mach01) return "";
  std::string wall;
  for (int f = 0; f < 6; ++f) {
    const int a = f / 2;
    const bool edge = f % 2 == 0 ? cell[a] == 0 : cell[a] == s_.cells[a] - 1;
    if (edge && s_.cells[a] > 1 && s_.faces[f].type == FaceType::wall) wall = face_names()[f];
  }
  return fmt::format(
      "The point particles' momentum source reaches {:.3g} N/m^3 in cell ({}, {}, {}){}; against viscosity alone "
      "it drives f dx^2/mu = {:.3g} m/s across a cell, more than the {:.3g} m/s of Mach 0.1. {}Remedies: let "
      "them leave (particles.boundaries: outlet on that face), particles.coupling: one-way, or coarser cells "
      "(f dx^2/mu falls as 1/dx). ",
      best.f, cell[0], cell[1], cell[2], wall.empty() ? "" : fmt::format(", next to the {} wall", wall), drive,
      mach01,
      wall.empty() ? "" : "Point particles that settle on a wall keep falling onto it step after step and pass "
                          "their weight to the cells next to it through drag (coflow's point particles have no "
                          "resting contact). ");
}

void LbmSolver::set_solid(std::span<const long> cells, std::span<const double> fraction,
                          std::span<const double> velocity, std::span<const double> wetting) {
  core_->set_psm(cells, fraction, wetting);
  solid_cells_.assign(cells.begin(), cells.end());
  solid_fraction_.assign(fraction.begin(), fraction.end());
  solid_us_.resize(velocity.size());
  for (std::size_t n = 0; n < velocity.size(); ++n) solid_us_[n] = velocity[n] / s_.units.velocity();
  solid_gain_.assign(3 * cells.size(), 0.0);
  solid_steps_ = 0;
}

void LbmSolver::set_source(std::span<const double> force_density) {
  source_si_.assign(force_density.begin(), force_density.end());
  std::vector<double> lattice(force_density.size());
  for (std::size_t n = 0; n < lattice.size(); ++n) lattice[n] = force_density[n] / s_.units.force_density();
  core_->set_source(lattice);
}

// Ladd's momentum exchange at the walls and interior solids (boundaries.hpp,
// the two-fluid core), summed by the core per cell over the steps since the
// last call and added exactly: one lattice momentum unit is rho dx^3 dx/dt of
// impulse.
coupler::ExactSums LbmSolver::take_wall_impulse() {
  const auto& u = s_.units;
  return core_->take_wall_momentum(u.rho * u.dx * u.dx * u.dx * u.velocity());
}

void LbmSolver::take_solid_force(std::vector<double>& force) {
  // The fluid gained sum_q B Omega^s_q e_q of lattice momentum per step; the solid
  // received the opposite (seed 000 eqs 2.69-2.70). One lattice momentum unit is
  // rho dx^3 dx/dt; averaged over the steps, per time step dt.
  const auto& u = s_.units;
  const double scale = solid_steps_ > 0 ? -u.rho * u.dx * u.dx * u.dx * u.velocity() / (solid_steps_ * u.dt) : 0.0;
  force.resize(solid_gain_.size());
  for (std::size_t n = 0; n < force.size(); ++n) force[n] = scale * solid_gain_[n];
  std::fill(solid_gain_.begin(), solid_gain_.end(), 0.0);
  solid_steps_ = 0;
}

void LbmSolver::save(const std::string& dir) {
  std::vector<double> f;
  core_->get_populations(f);
  const auto& c = s_.cells;
  grid::save_cell_fields(comm_, dir + "/lbm.h5", time(), steps_, {c[0], c[1], c[2]}, owned_,
                         {{"populations", core_->q(), f}});
  // The largest u^2 of the last step over all ranks: the immersed boundaries'
  // velocity scale in the first step after a restart (their tolerance).
  double u2 = core_->max_u2();
  MPI_Allreduce(MPI_IN_PLACE, &u2, 1, MPI_DOUBLE, MPI_MAX, comm_);
  grid::save_number(comm_, dir + "/lbm_max_u2.txt", u2);
  grid::save_number(comm_, dir + "/lbm_offset.txt", core_->stored_offset().empty() ? 0.0 : 1.0);
}

void LbmSolver::load(const std::string& dir, long steps, double) {
  const auto& c = s_.cells;
  auto f = grid::load_cell_field(dir + "/lbm.h5", "populations", {c[0], c[1], c[2]}, owned_, core_->q());
  // lbm-reference's checkpoint holds the whole populations f (lbm_offset.txt
  // 0); one written before that file was is this variant's own.
  const std::vector<double> w = core_->stored_offset();
  if (!w.empty() && grid::load_number(dir + "/lbm_offset.txt", 1.0) == 0.0)
    for (std::size_t n = 0; n < f.size(); ++n) f[n] -= w[n % w.size()];
  core_->set_populations(f);
  core_->set_max_u2(grid::load_number(dir + "/lbm_max_u2.txt", 0.0));
  steps_ = steps;
}

std::vector<output::GridField> LbmSolver::fields(const config::StringList& names) {
  core_->macroscopic(out_u_, out_rho_);
  out_p_.resize(out_rho_.size());
  const double cu = s_.units.velocity();
  for (auto& v : out_u_) v *= cu;
  for (std::size_t c = 0; c < out_rho_.size(); ++c) {
    out_p_[c] = s_.units.pressure_of(out_rho_[c]);
    out_rho_[c] *= s_.units.rho;
  }
  std::vector<output::GridField> f;
  for (const auto& n : names) {
    if (n == "velocity") f.push_back({n, 3, out_u_});
    if (n == "pressure") f.push_back({n, 1, out_p_});
    if (n == "density") f.push_back({n, 1, out_rho_});
    if (n == "solid_fraction") {  // interior solids (1), partially saturated cells (psm); zero elsewhere
      if (!core_->solid_mask(out_solid_)) out_solid_.assign(out_rho_.size(), 0.0);
      for (std::size_t c = 0; c < solid_cells_.size(); ++c) out_solid_[solid_cells_[c]] = solid_fraction_[c];
      f.push_back({n, 1, out_solid_});
    }
    if (n == "phase") {  // (rho_r - rho_b) / (rho_r + rho_b); one fluid: 1 (red); solids: 0
      if (!core_->phase(out_phase_)) out_phase_.assign(out_rho_.size(), 1.0);
      f.push_back({n, 1, out_phase_});
    }
  }
  return f;
}

Diagnostics LbmSolver::diagnostics() {
  std::vector<double> u, rho;
  core_->macroscopic(u, rho);
  std::vector<double>& solid = out_solid_;
  const bool solids = core_->solid_mask(solid);  // interior solids hold no fluid
  const double vol = std::pow(s_.units.dx, 3), cu = s_.units.velocity();
  double local[5] = {0, 0, 0, 0, 0}, umax = 0.0;
  for (std::size_t c = 0; c < rho.size(); ++c) {
    if (solids && solid[c] > 0.0) continue;
    const double rho_m = s_.incompressible ? 1.0 : rho[c];
    const double m = rho_m * s_.units.rho * vol;
    local[0] += rho[c] * s_.units.rho * vol;
    double uu = 0;
    for (int k = 0; k < 3; ++k) {
      local[1 + k] += m * u[3 * c + k] * cu;
      uu += u[3 * c + k] * u[3 * c + k];
    }
    local[4] += 0.5 * m * uu * cu * cu;
    umax = std::max(umax, std::sqrt(uu));
  }
  double global[5], gmax = 0.0;
  MPI_Allreduce(local, global, 5, MPI_DOUBLE, MPI_SUM, comm_);
  MPI_Allreduce(&umax, &gmax, 1, MPI_DOUBLE, MPI_MAX, comm_);
  Diagnostics d;
  d.mass = global[0];
  d.momentum = {global[1], global[2], global[3]};
  d.kinetic_energy = global[4];
  d.max_velocity = gmax * cu;
  d.max_mach = gmax / std::sqrt(lbm::cs2);
  if (s_.tp.on) {
    core_->phase(out_phase_);
    if (!solids) out_solid_.assign(rho.size(), 0.0);
    if (solid_cells_.empty() || !core_->grain_fractions(out_grain_)) out_grain_.clear();
    d.extra = lbm::phase_values(s_.units, s_.cells, rho, u, out_phase_, out_solid_, out_grain_, comm_);
  }
  return d;
}

std::vector<output::Series::Column> LbmSolver::series_columns() const {
  return s_.tp.on ? lbm::phase_columns() : std::vector<output::Series::Column>{};
}

}  // namespace coflow::fluid
