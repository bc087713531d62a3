#include "fluid/fv/struct_system.hpp"

#include <HYPRE_krylov.h>
#include <HYPRE_struct_ls.h>
#include <_hypre_struct_mv.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "coflow/log.hpp"
#include "fluid/fv/row_sums.hpp"

namespace coflow::fluid::fv {

struct StructSystem::Hypre {
  HYPRE_StructGrid grid = nullptr;
  HYPRE_StructStencil stencil = nullptr;
  HYPRE_StructMatrix A = nullptr;
  HYPRE_StructVector b = nullptr, x = nullptr;
  HYPRE_StructSolver pcg = nullptr, precond = nullptr;
  MPI_Comm comm;
  HYPRE_Int lo[3], hi[3];
  bool ready = false;  // the solver is set up for the matrix
  // The diagonal PCG's search direction p lives in a hypre vector, whose
  // ghost cells hypre's communication package fills from the neighbours
  // (and the periodic images); its residual r and A p in owned cells.
  HYPRE_StructVector p = nullptr;
  hypre_CommPkg* halo = nullptr;
  std::vector<long> p_rows;  // where each row along x of the owned box starts in p's storage
  long p_stride[3] = {1, 0, 0};
  std::vector<double> r, s;
};

namespace {

// Where each row along x of the owned box [lo, hi] starts in a vector's storage.
std::vector<long> row_starts(HYPRE_StructVector v, const HYPRE_Int* lo, const HYPRE_Int* hi) {
  auto* sv = reinterpret_cast<hypre_StructVector*>(v);
  hypre_Box* box = hypre_BoxArrayBox(hypre_StructVectorDataSpace(sv), 0);
  const long base = hypre_StructVectorDataIndices(sv)[0];
  std::vector<long> rows;
  for (HYPRE_Int k = lo[2]; k <= hi[2]; ++k)
    for (HYPRE_Int j = lo[1]; j <= hi[1]; ++j) {
      hypre_Index at;
      hypre_SetIndex3(at, lo[0], j, k);
      rows.push_back(base + hypre_BoxIndexRank(box, at));
    }
  return rows;
}

}  // namespace

StructSystem::StructSystem(MPI_Comm comm, const coupler::Box& owned, const coupler::Index3& cells,
                           const std::array<bool, 3>& periodic, Options opt)
    : h_(new Hypre), opt_(std::move(opt)), dims_(cells[2] == 1 ? 2 : 3) {
  h_->comm = comm;
  HYPRE_Int period[3] = {0, 0, 0};
  for (int d = 0; d < 3; ++d) {
    h_->lo[d] = static_cast<HYPRE_Int>(owned.lo[d]);
    h_->hi[d] = static_cast<HYPRE_Int>(owned.hi[d] - 1);
    if (periodic[d] && d < dims_) period[d] = static_cast<HYPRE_Int>(cells[d]);
    if (periodic[d] && d < dims_) red_black_ = false;
  }
  if (dims_ == 3) red_black_ = false;  // in 3D more iterations than it saves (bench-fv: 17.8 against 15.0)
  HYPRE_StructGridCreate(comm, dims_, &h_->grid);
  HYPRE_StructGridSetExtents(h_->grid, h_->lo, h_->hi);
  HYPRE_StructGridSetPeriodic(h_->grid, period);
  HYPRE_StructGridAssemble(h_->grid);
  // Entries: the centre, then lower and upper along each axis.
  HYPRE_StructStencilCreate(dims_, 1 + 2 * dims_, &h_->stencil);
  HYPRE_Int zero[3] = {0, 0, 0};
  HYPRE_StructStencilSetElement(h_->stencil, 0, zero);
  for (int d = 0; d < dims_; ++d)
    for (int s = 0; s < 2; ++s) {
      HYPRE_Int off[3] = {0, 0, 0};
      off[d] = s == 0 ? -1 : 1;
      HYPRE_StructStencilSetElement(h_->stencil, 1 + 2 * d + s, off);
    }
  HYPRE_StructMatrixCreate(comm, h_->grid, h_->stencil, &h_->A);
  HYPRE_StructMatrixInitialize(h_->A);
  HYPRE_StructVectorCreate(comm, h_->grid, &h_->b);
  HYPRE_StructVectorCreate(comm, h_->grid, &h_->x);
  HYPRE_StructVectorInitialize(h_->b);
  HYPRE_StructVectorInitialize(h_->x);
  HYPRE_StructVectorCreate(comm, h_->grid, &h_->p);
  HYPRE_StructVectorInitialize(h_->p);
  HYPRE_StructVectorSetConstantValues(h_->p, 0.0);
  auto* P = reinterpret_cast<hypre_StructVector*>(h_->p);
  h_->p_rows = row_starts(h_->p, h_->lo, h_->hi);
  hypre_Box* box = hypre_BoxArrayBox(hypre_StructVectorDataSpace(P), 0);
  h_->p_stride[1] = hypre_BoxSizeX(box), h_->p_stride[2] = hypre_BoxSizeX(box) * hypre_BoxSizeY(box);
  // The exchange of p's ghost cells, as hypre's own matrix-vector product sets it up.
  hypre_CommInfo* info = nullptr;
  hypre_CreateCommInfoFromStencil(reinterpret_cast<hypre_StructGrid*>(h_->grid),
                                  reinterpret_cast<hypre_StructStencil*>(h_->stencil), &info);
  hypre_CommPkgCreate(info, hypre_StructVectorDataSpace(P), hypre_StructVectorDataSpace(P), 1, nullptr, 0,
                      comm, &h_->halo);
  hypre_CommInfoDestroy(info);
}

StructSystem::~StructSystem() {
  free_solver();
  hypre_CommPkgDestroy(h_->halo);
  HYPRE_StructVectorDestroy(h_->p);
  HYPRE_StructVectorDestroy(h_->x);
  HYPRE_StructVectorDestroy(h_->b);
  HYPRE_StructMatrixDestroy(h_->A);
  HYPRE_StructStencilDestroy(h_->stencil);
  HYPRE_StructGridDestroy(h_->grid);
  delete h_;
}

void StructSystem::use_diagonal(bool on) {
  if (on == diagonal_) return;
  free_solver();
  diagonal_ = on;
}

void StructSystem::free_solver() {
  if (!h_->ready) return;
  HYPRE_StructPCGDestroy(h_->pcg);
  if (opt_.multigrid == "smg")
    HYPRE_StructSMGDestroy(h_->precond);
  else
    HYPRE_StructPFMGDestroy(h_->precond);
  h_->ready = false;
}

void StructSystem::set(std::span<const double> diag, const Couplings& lower, const Couplings& upper) {
  rows_.resize(diag.size());
  std::copy(diag.begin(), diag.end(), rows_.diag.begin());
  for (std::size_t d = 0; d < 3; ++d) {
    std::copy(lower[d].begin(), lower[d].end(), rows_.lower[d].begin());
    std::copy(upper[d].begin(), upper[d].end(), rows_.upper[d].begin());
  }
  changed();
}

void StructSystem::take(Rows& r) {
  std::swap(rows_, r);
  changed();
}

// A multigrid's coarse operators depend on the values; the diagonal PCG reads
// them when it runs.
void StructSystem::changed() {
  stale_ = inv_stale_ = sym_stale_ = true;
  if (!diagonal_) free_solver();
}

// hypre's copy of the matrix, for its multigrid: straight into its storage of
// this rank's one box, a row of x at a time.
void StructSystem::sync_hypre() {
  if (!stale_) return;
  auto* A = static_cast<hypre_StructMatrix*>(h_->A);
  hypre_Box* data_box = hypre_StructMatrixBox(A, 0);
  const long nx = h_->hi[0] - h_->lo[0] + 1, ny = h_->hi[1] - h_->lo[1] + 1, nz = h_->hi[2] - h_->lo[2] + 1;
  for (int e = 0; e < 1 + 2 * dims_; ++e) {
    const auto D = static_cast<std::size_t>((e - 1) / 2);
    const double* from = e == 0 ? rows_.diag.data() : (e % 2 == 1 ? rows_.lower : rows_.upper)[D].data();
    HYPRE_Complex* to = hypre_StructMatrixBoxData(A, 0, e);
    for (long k = 0; k < nz; ++k)
      for (long j = 0; j < ny; ++j) {
        hypre_Index at;
        hypre_SetIndex3(at, h_->lo[0], h_->lo[1] + j, h_->lo[2] + k);
        std::copy_n(from + (k * ny + j) * nx, nx, to + hypre_BoxIndexRank(data_box, at));
      }
  }
  HYPRE_StructMatrixAssemble(h_->A);
  stale_ = false;
}

// s = A p, p in hypre's storage (its ghost cells filled from the neighbours
// first), s and the matrix in owned cells. A coupling across a wall is zero
// and the ghost cells there stay zero. With a matrix symmetric in the block
// (symmetric_, row_asymmetries) a cell's couplings to its lower neighbours
// inside the block are read as those neighbours' upper ones: the same
// numbers in the same sums, two of the seven streams of the loop fewer (in
// bench-fv's k-epsilon channel the viscous, k and epsilon solves are a third
// of the step). Returns p . s on this rank, each row's part added
// (row_sums) while it is in cache.
double StructSystem::matvec(const double* p, std::vector<double>& s) {
  hypre_CommHandle* handle = nullptr;
  auto* data = hypre_StructVectorData(reinterpret_cast<hypre_StructVector*>(h_->p));
  hypre_InitializeCommunication(h_->halo, data, data, 0, 0, &handle);
  hypre_FinalizeCommunication(handle);
  const long nx = h_->hi[0] - h_->lo[0] + 1, ny = h_->hi[1] - h_->lo[1] + 1;
  const long rows = static_cast<long>(h_->p_rows.size());
  const long sy = h_->p_stride[1], sz = dims_ == 3 ? h_->p_stride[2] : 0;
  const Rows& m = rows_;
  // The first product with a new matrix takes the general path and checks
  // the symmetry row by row, the rows in cache.
  const bool check = sym_stale_, sym = symmetric_ && !check;
  long differ = 0;
  double ps = 0.0;
  for (long j = 0; j < rows; ++j) {
    const double* __restrict pr = p + h_->p_rows[static_cast<std::size_t>(j)];
    const auto o = static_cast<std::size_t>(j * nx);
    const double *__restrict dg = m.diag.data() + o, *__restrict u0 = m.upper[0].data() + o,
                             *__restrict u1 = m.upper[1].data() + o;
    // lower[0][o + i] is upper[0][o + i - 1] from the row's second cell on
    // (w0[i - shift]: no pointer before the array's start).
    const double* __restrict w0 = sym ? u0 : m.lower[0].data() + o;
    const long shift = sym ? 1 : 0;
    const double* __restrict l1 = sym && j % ny > 0 ? u1 - nx : m.lower[1].data() + o;
    double* __restrict out = s.data() + o;
    const long first = sym ? 1 : 0;
    if (sym)
      out[0] = dg[0] * pr[0] + m.lower[0][o] * pr[-1] + u0[0] * pr[1] + l1[0] * pr[-sy] + u1[0] * pr[sy];
    for (long i = first; i < nx; ++i)
      out[i] = dg[i] * pr[i] + w0[i - shift] * pr[i - 1] + u0[i] * pr[i + 1] + l1[i] * pr[i - sy] +
               u1[i] * pr[i + sy];
    if (sz > 0) {
      const double* __restrict u2 = m.upper[2].data() + o;
      const double* __restrict l2 = sym && j / ny > 0 ? u2 - nx * ny : m.lower[2].data() + o;
      for (long i = 0; i < nx; ++i) out[i] += l2[i] * pr[i - sz] + u2[i] * pr[i + sz];
    }
    row_sums(nx, &ps, 1, [&](long i, auto a) { a[0] += pr[i] * out[i]; });
    if (check) differ += row_asymmetries(j);
  }
  if (check) symmetric_ = differ == 0, sym_stale_ = false;
  return ps;
}

// How many cells of owned row j have a coupling to a lower neighbour inside
// the block that differs from that neighbour's coupling back (a NaN differs).
long StructSystem::row_asymmetries(long j) const {
  const long nx = h_->hi[0] - h_->lo[0] + 1, ny = h_->hi[1] - h_->lo[1] + 1;
  const Rows& m = rows_;
  const auto o = static_cast<std::size_t>(j * nx);
  long differ = 0;
  const double* __restrict l0 = m.lower[0].data() + o, * __restrict u0 = m.upper[0].data() + o;
  for (long i = 1; i < nx; ++i) differ += l0[i] != u0[i - 1];
  for (int d = 1; d < dims_; ++d) {
    const long below = d == 1 ? nx : nx * ny;  // the neighbour's offset in owned cells
    if (d == 1 ? j % ny == 0 : j / ny == 0) continue;
    const auto D = static_cast<std::size_t>(d);
    const double* __restrict l = m.lower[D].data() + o;
    const double* __restrict u = m.upper[D].data() + o - below;
    for (long i = 0; i < nx; ++i) differ += l[i] != u[i];
  }
  return differ;
}

// Conjugate gradients preconditioned by the diagonal (Jacobi), written out
// here instead of hypre's PCG with HYPRE_StructDiagScale: the same iteration
// and stopping rule (the 2-norm of the residual relative to b's, or below the
// floor), but three passes over the cells per iteration besides the product
// with A where hypre makes eight, its inner products one chain of adds, and
// the matrix read where the caller assembled it. In bench-fv's k-epsilon
// channel (four such solves a step) hypre's vector operations and the copies
// into its matrix were a quarter of the step.
void StructSystem::solve_diagonal(std::span<const double> b, std::span<double> x) {
  const long nx = h_->hi[0] - h_->lo[0] + 1, rows = static_cast<long>(h_->p_rows.size());
  double* P = hypre_StructVectorData(reinterpret_cast<hypre_StructVector*>(h_->p));
  auto &r = h_->r, &S = h_->s;
  if (rows_.diag.size() != b.size() || x.size() != b.size())
    throw std::logic_error("StructSystem::solve: no matrix, or vectors of another size than its rows");
  r.resize(b.size()), S.resize(b.size());
  if (inv_stale_) {
    inv_diag_.resize(rows_.diag.size());
    for (std::size_t i = 0; i < inv_diag_.size(); ++i) inv_diag_[i] = 1.0 / rows_.diag[i];
    inv_stale_ = false;
  }
  const double* id = inv_diag_.data();
  auto each_row = [&](auto&& f) {
    for (long j = 0; j < rows; ++j) f(j * nx, P + h_->p_rows[static_cast<std::size_t>(j)], S.data() + j * nx);
  };
  each_row([&](long o, double* p, const double*) { std::copy_n(x.data() + o, nx, p); });
  matvec(P, S);
  double sums[3] = {0.0, 0.0, 0.0};  // b.b, then r.r and r.z (z = r / diag)
  each_row([&](long o, double* p, const double* s) {
    row_sums(nx, sums, 1, [&](long i, auto a) { a[0] += b[o + i] * b[o + i]; });
    row_sums(nx, sums + 1, 2, [&](long i, auto a) {
      const double ri = b[o + i] - s[i], zi = ri * id[o + i];
      r[o + i] = ri, p[i] = zi, a[0] += ri * ri, a[1] += ri * zi;
    });
  });
  MPI_Allreduce(MPI_IN_PLACE, sums, 3, MPI_DOUBLE, MPI_SUM, h_->comm);
  const double bb = sums[0], limit = std::max(opt_.tolerance * opt_.tolerance * bb, floor_ * floor_);
  double rr = sums[1], rz = sums[2];
  int it = 0;
  if (!std::isfinite(bb)) throw std::runtime_error(rhs_not_finite(opt_.name, bb));
  if (bb == 0.0) std::fill(x.begin(), x.end(), 0.0), rr = 0.0;  // as hypre: b = 0 gives x = 0
  // At least one iteration, as hypre's PCG: a first guess already within the
  // tolerance still gets closer (a steady flow's residual would otherwise
  // build up over the steps).
  while ((it == 0 || !(rr <= limit)) && bb > 0.0 && it < opt_.max_iterations && std::isfinite(rr)) {
    double ps = matvec(P, S);
    MPI_Allreduce(MPI_IN_PLACE, &ps, 1, MPI_DOUBLE, MPI_SUM, h_->comm);
    if (ps == 0.0) break;  // p = 0 (a breakdown): judged below by the residual
    const double alpha = rz / ps;
    double next[2] = {0.0, 0.0};  // r.r, r.z
    each_row([&](long o, double* p, const double* s) {
      row_sums(nx, next, 2, [&](long i, auto a) {
        const double ri = r[o + i] - alpha * s[i];
        r[o + i] = ri, a[0] += ri * ri, a[1] += ri * ri * id[o + i];
      });
    });
    MPI_Allreduce(MPI_IN_PLACE, next, 2, MPI_DOUBLE, MPI_SUM, h_->comm);
    const double beta = next[1] / rz;
    rr = next[0], rz = next[1], ++it;
    // x += alpha p where p is read anyway: with the next direction, or alone
    // at the last iteration.
    if (rr <= limit) {
      each_row([&](long o, double* p, const double*) {
        for (long i = 0; i < nx; ++i) x[o + i] += alpha * p[i];
      });
      break;
    }
    each_row([&](long o, double* p, const double*) {
      for (long i = 0; i < nx; ++i) x[o + i] += alpha * p[i], p[i] = r[o + i] * id[o + i] + beta * p[i];
    });
  }
  iterations_ = it;
  residual_ = bb > 0.0 ? std::sqrt(rr / bb) : 0.0;
  if (!(rr <= limit))  // out of iterations, a breakdown, or not finite
    throw std::runtime_error(not_converged(opt_.name, residual_, it, opt_.tolerance));
}

// Conjugate gradients (2-norm of the residual relative to the right-hand side)
// preconditioned by one multigrid V-cycle from a zero guess: PFMG with
// weighted Jacobi, one sweep down and one up (symmetric, as PCG needs), or SMG.
void StructSystem::make_solver() {
  HYPRE_StructPCGCreate(h_->comm, &h_->pcg);
  HYPRE_StructPCGSetTol(h_->pcg, opt_.tolerance);
  HYPRE_StructPCGSetMaxIter(h_->pcg, opt_.max_iterations);
  HYPRE_StructPCGSetTwoNorm(h_->pcg, 1);
  HYPRE_StructPCGSetRelChange(h_->pcg, 0);
  HYPRE_StructPCGSetAbsoluteTol(h_->pcg, floor_);
  if (opt_.multigrid == "smg") {
    HYPRE_StructSMGCreate(h_->comm, &h_->precond);
    HYPRE_StructSMGSetMaxIter(h_->precond, 1);
    HYPRE_StructSMGSetTol(h_->precond, 0.0);
    HYPRE_StructSMGSetZeroGuess(h_->precond);
    HYPRE_StructSMGSetNumPreRelax(h_->precond, 1);
    HYPRE_StructSMGSetNumPostRelax(h_->precond, 1);
    HYPRE_StructPCGSetPrecond(h_->pcg, HYPRE_StructSMGSolve, HYPRE_StructSMGSetup, h_->precond);
  } else {
    HYPRE_StructPFMGCreate(h_->comm, &h_->precond);
    HYPRE_StructPFMGSetMaxIter(h_->precond, 1);
    HYPRE_StructPFMGSetTol(h_->precond, 0.0);
    HYPRE_StructPFMGSetZeroGuess(h_->precond);
    // Symmetric red-black Gauss-Seidel in 2D (fewer, cheaper iterations), but
    // weighted Jacobi in 3D and on a grid with a periodic axis: PFMG's coarsening
    // reaches periodic extents (odd, or a single cell) where red and black
    // neighbours meet across the period, the smoother is no longer symmetric
    // and PCG stalls (seen on a 4-cell periodic channel).
    HYPRE_StructPFMGSetRelaxType(h_->precond, red_black_ ? 2 : 1);
    HYPRE_StructPFMGSetNumPreRelax(h_->precond, 1);
    HYPRE_StructPFMGSetNumPostRelax(h_->precond, 1);
    HYPRE_StructPCGSetPrecond(h_->pcg, HYPRE_StructPFMGSolve, HYPRE_StructPFMGSetup, h_->precond);
  }
  HYPRE_StructPCGSetup(h_->pcg, h_->A, h_->b, h_->x);
  h_->ready = true;
}

void StructSystem::set_absolute_floor(double floor) {
  if (floor == floor_) return;
  floor_ = floor;
  if (h_->ready) HYPRE_StructPCGSetAbsoluteTol(h_->pcg, floor_);
}

void StructSystem::solve(std::span<const double> b, std::span<double> x) {
  if (diagonal_) return solve_diagonal(b, x);
  sync_hypre();
  HYPRE_StructVectorSetBoxValues(h_->b, h_->lo, h_->hi, const_cast<double*>(b.data()));
  HYPRE_StructVectorSetBoxValues(h_->x, h_->lo, h_->hi, x.data());
  HYPRE_StructVectorAssemble(h_->b);
  HYPRE_StructVectorAssemble(h_->x);
  if (!h_->ready) make_solver();
  HYPRE_StructPCGSolve(h_->pcg, h_->A, h_->b, h_->x);
  HYPRE_Int it = 0, converged = 0;  // converged: hypre's test passed (relative tolerance or absolute floor)
  HYPRE_StructPCGGetNumIterations(h_->pcg, &it);
  HYPRE_StructPCGGetFinalRelativeResidualNorm(h_->pcg, &residual_);
  HYPRE_PCGGetConverged(reinterpret_cast<HYPRE_Solver>(h_->pcg), &converged);
  iterations_ = static_cast<int>(it);
  HYPRE_ClearAllErrors();  // non-convergence is judged below
  HYPRE_StructVectorGetBoxValues(h_->x, h_->lo, h_->hi, x.data());
  if (!converged) judge_early_stop(b, x);
}

// PCG also stops short of its tolerance when <p, A p> or <r, M r> is not
// positive: a matrix or a preconditioner that is not positive definite
// (SMG on a periodic axis of 20 cells: backward errors 0.06 to 0.2), or
// round-off in a singular system (PFMG on a closed 320 x 160 box asked for
// 1e-13 stops at 1.8e-9, a backward error of 5e-12), or a NaN. hypre's
// residual is then not reliable (it may be the previous solve's): the true
// one decides, b = 0 (x = 0) included. A stop whose normwise backward
// error |r| / (|A| |x| + |b|) (Rigal & Gaches 1967; Higham 2002 §7.1) is
// within sqrt(eps) = 1.5e-8, half of double's digits, is accepted once with
// a warning; anything else is an error.
void StructSystem::judge_early_stop(std::span<const double> b, std::span<const double> x) {
  const Residual r = true_residual(b, x);
  residual_ = r.relative;
  // A lid at 1e160 m/s squares past double's range: hypre stops at once, and
  // |r|^2 <= tol^2 |b|^2 read inf <= inf, so the flow stayed at rest and the
  // run "finished" (the geometric multigrid and the diagonal path check b too).
  if (!std::isfinite(r.bb)) throw std::runtime_error(rhs_not_finite(opt_.name, r.bb));
  if (r.within(opt_.tolerance, floor_)) return;
  if (iterations_ < opt_.max_iterations && r.backward <= 1.5e-8) {
    int rank = 0;
    MPI_Comm_rank(h_->comm, &rank);
    if (!warned_ && rank == 0)
      log::warn(
          "fv: the {}'s conjugate gradients stopped at relative residual {:.3g} (tolerance {:.3g}), "
          "a backward error of {:.2g}: the rounding limit of this system; accepted (warned once)",
          opt_.name, residual_, opt_.tolerance, r.backward);
    warned_ = true;
    return;
  }
  if (iterations_ < opt_.max_iterations || !std::isfinite(r.backward))
    throw std::runtime_error(fmt::format(
        "fv: the {}'s conjugate gradients broke down after {} iterations at relative residual {:.3g} "
        "(tolerance {:.3g}; a backward error of {:.2g}, above rounding's 1.5e-8): its matrix or the {} "
        "preconditioner is not symmetric positive definite, or the flow is blowing up (lower fluid.fv.cfl)",
        opt_.name, iterations_, residual_, opt_.tolerance, r.backward, opt_.multigrid));
  throw std::runtime_error(not_converged(opt_.name, residual_, iterations_, opt_.tolerance));
}

// r = b - A x by matvec (x through p's storage), over all ranks.
StructSystem::Residual StructSystem::true_residual(std::span<const double> b, std::span<const double> x) {
  const long nx = h_->hi[0] - h_->lo[0] + 1, rows = static_cast<long>(h_->p_rows.size());
  double* P = hypre_StructVectorData(reinterpret_cast<hypre_StructVector*>(h_->p));
  auto& S = h_->s;
  S.resize(b.size());
  for (long j = 0; j < rows; ++j)
    std::copy_n(x.data() + j * nx, nx, P + h_->p_rows[static_cast<std::size_t>(j)]);
  matvec(P, S);
  double sums[3] = {0.0, 0.0, 0.0}, norm_a = 0.0;  // r.r, b.b, x.x; the largest row sum of |A|
  for (std::size_t c = 0; c < b.size(); ++c) {
    sums[0] += (b[c] - S[c]) * (b[c] - S[c]), sums[1] += b[c] * b[c], sums[2] += x[c] * x[c];
    double a = std::fabs(rows_.diag[c]);
    for (std::size_t d = 0; d < 3; ++d) a += std::fabs(rows_.lower[d][c]) + std::fabs(rows_.upper[d][c]);
    norm_a = std::max(norm_a, std::isnan(a) ? HUGE_VAL : a);
  }
  MPI_Allreduce(MPI_IN_PLACE, sums, 3, MPI_DOUBLE, MPI_SUM, h_->comm);
  MPI_Allreduce(MPI_IN_PLACE, &norm_a, 1, MPI_DOUBLE, MPI_MAX, h_->comm);
  Residual r{sums[0], sums[1]};
  r.relative = sums[1] > 0.0 ? std::sqrt(sums[0] / sums[1]) : 0.0;
  // |A|_2 <= max row sum for a symmetric matrix.
  const double scale = norm_a * std::sqrt(sums[2]) + std::sqrt(sums[1]);
  r.backward = scale > 0.0 ? std::sqrt(sums[0]) / scale : 0.0;
  if (!std::isfinite(sums[0])) r.backward = NAN;
  return r;
}

std::string rhs_not_finite(const std::string& name, double bb) {
  return fmt::format(
      "fv: the {}'s right-hand side is not finite (|b|^2 = {}): the flow is blowing up (lower fluid.fv.cfl), "
      "or "
      "a boundary, initial or force value is beyond what double precision can square (about 1e154)",
      name, bb);
}

std::string not_converged(const std::string& name, double residual, long iterations, double tolerance) {
  return fmt::format(
      "fv: the {} did not converge: relative residual {:.3g} after {} iterations (tolerance {:.3g}); raise "
      "fluid.fv.max_iterations or fluid.fv.tolerance, or lower fluid.fv.cfl if the flow is blowing up",
      name, residual, iterations, tolerance);
}

void StructSystem::cycle(std::span<const double> b, std::span<double> x) {
  if (diagonal_) throw std::logic_error("StructSystem::cycle: no multigrid with the diagonal preconditioner");
  HYPRE_StructVectorSetBoxValues(h_->b, h_->lo, h_->hi, const_cast<double*>(b.data()));
  HYPRE_StructVectorAssemble(h_->b);
  HYPRE_StructVectorSetConstantValues(h_->x, 0.0);
  sync_hypre();
  if (!h_->ready) make_solver();
  if (opt_.multigrid == "smg")
    HYPRE_StructSMGSolve(h_->precond, h_->A, h_->b, h_->x);
  else
    HYPRE_StructPFMGSolve(h_->precond, h_->A, h_->b, h_->x);
  HYPRE_StructVectorGetBoxValues(h_->x, h_->lo, h_->hi, x.data());
}

}  // namespace coflow::fluid::fv
