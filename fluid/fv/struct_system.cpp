#include "fluid/fv/struct_system.hpp"

#include <HYPRE_struct_ls.h>
#include <_hypre_struct_mv.h>
#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

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
};

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
}

StructSystem::~StructSystem() {
  free_solver();
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
  if (diagonal_)
    ;  // no preconditioner object
  else if (opt_.multigrid == "smg")
    HYPRE_StructSMGDestroy(h_->precond);
  else
    HYPRE_StructPFMGDestroy(h_->precond);
  h_->ready = false;
}

void StructSystem::set(std::span<const double> diag, const Couplings& lower, const Couplings& upper) {
  // The entries go straight into hypre's storage of this rank's one box, a
  // row of x at a time (HYPRE_StructMatrixSetBoxValues takes them interleaved
  // per cell, and that copy was 4 % of a k-epsilon step in bench-fv's
  // channel, whose matrices change every step).
  auto* A = static_cast<hypre_StructMatrix*>(h_->A);
  hypre_Box* data_box = hypre_StructMatrixBox(A, 0);
  const long nx = h_->hi[0] - h_->lo[0] + 1, ny = h_->hi[1] - h_->lo[1] + 1, nz = h_->hi[2] - h_->lo[2] + 1;
  for (int e = 0; e < 1 + 2 * dims_; ++e) {
    const double* from = e == 0 ? diag.data() : (e % 2 == 1 ? lower : upper)[(e - 1) / 2].data();
    HYPRE_Complex* to = hypre_StructMatrixBoxData(A, 0, e);
    for (long k = 0; k < nz; ++k)
      for (long j = 0; j < ny; ++j) {
        hypre_Index at;
        hypre_SetIndex3(at, h_->lo[0], h_->lo[1] + j, h_->lo[2] + k);
        std::copy_n(from + (k * ny + j) * nx, nx, to + hypre_BoxIndexRank(data_box, at));
      }
  }
  HYPRE_StructMatrixAssemble(h_->A);
  // The diagonal preconditioner and the conjugate gradients read the matrix's
  // values when they run (their setup depends on its structure alone), so new
  // values need no new setup; a multigrid's coarse operators do.
  if (!diagonal_) free_solver();
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
  if (diagonal_) {
    HYPRE_StructPCGSetPrecond(h_->pcg, HYPRE_StructDiagScale, HYPRE_StructDiagScaleSetup, nullptr);
  } else if (opt_.multigrid == "smg") {
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
  HYPRE_StructVectorSetBoxValues(h_->b, h_->lo, h_->hi, const_cast<double*>(b.data()));
  HYPRE_StructVectorSetBoxValues(h_->x, h_->lo, h_->hi, x.data());
  HYPRE_StructVectorAssemble(h_->b);
  HYPRE_StructVectorAssemble(h_->x);
  if (!h_->ready) make_solver();
  HYPRE_StructPCGSolve(h_->pcg, h_->A, h_->b, h_->x);
  HYPRE_Int it = 0;
  HYPRE_StructPCGGetNumIterations(h_->pcg, &it);
  HYPRE_StructPCGGetFinalRelativeResidualNorm(h_->pcg, &residual_);
  iterations_ = static_cast<int>(it);
  HYPRE_ClearAllErrors();  // non-convergence is judged below, by the residual
  HYPRE_StructVectorGetBoxValues(h_->x, h_->lo, h_->hi, x.data());
  if (!(residual_ <= opt_.tolerance) && it >= opt_.max_iterations)
    throw std::runtime_error(not_converged(opt_.name, residual_, it, opt_.tolerance));
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
  if (!h_->ready) make_solver();
  if (opt_.multigrid == "smg")
    HYPRE_StructSMGSolve(h_->precond, h_->A, h_->b, h_->x);
  else
    HYPRE_StructPFMGSolve(h_->precond, h_->A, h_->b, h_->x);
  HYPRE_StructVectorGetBoxValues(h_->x, h_->lo, h_->hi, x.data());
}

}  // namespace coflow::fluid::fv
