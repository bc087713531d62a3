#include "fluid/fv/amr/ij_system.hpp"

#include <HYPRE.h>
#include <HYPRE_IJ_mv.h>
#include <HYPRE_parcsr_ls.h>
#include <fmt/format.h>

#include <limits>
#include <numeric>
#include <stdexcept>

namespace coflow::fluid::fv::amr {

struct IjSystem::Hypre {
  HYPRE_IJMatrix A = nullptr;
  HYPRE_IJVector b = nullptr, x = nullptr;
  HYPRE_ParCSRMatrix A_csr = nullptr;
  HYPRE_Solver gmres = nullptr, amg = nullptr;
  std::vector<HYPRE_BigInt> ids;  // the local rows' ids
  bool ready = false;             // the multigrid is set up for A
};

IjSystem::IjSystem(MPI_Comm comm, long first_row, const std::vector<Stencil>& rows, Options opt)
    : h_(new Hypre), comm_(comm), opt_(opt), first_(first_row), count_(static_cast<long>(rows.size())) {
  // Debian's hypre numbers rows with int (HYPRE_BigInt): more cells would
  // wrap. Every rank learns the largest row, so all throw or none.
  long last = first_row + count_ - 1;
  MPI_Allreduce(MPI_IN_PLACE, &last, 1, MPI_LONG, MPI_MAX, comm);
  if (last > static_cast<long>(std::numeric_limits<HYPRE_BigInt>::max())) {
    delete h_;
    throw std::runtime_error(fmt::format(
        "refinement: {} cells are more than this hypre numbers ({}, HYPRE_BigInt of {} bytes); use fewer "
        "levels or larger coarse cells, or a hypre built with 64-bit integers",
        last + 1, std::numeric_limits<HYPRE_BigInt>::max(), sizeof(HYPRE_BigInt)));
  }
  const auto lo = static_cast<HYPRE_BigInt>(first_row),
             hi = static_cast<HYPRE_BigInt>(first_row + count_ - 1);
  HYPRE_IJMatrixCreate(comm, lo, hi, lo, hi, &h_->A);
  HYPRE_IJMatrixSetObjectType(h_->A, HYPRE_PARCSR);
  std::vector<HYPRE_Int> sizes(rows.size());
  for (std::size_t r = 0; r < rows.size(); ++r) sizes[r] = static_cast<HYPRE_Int>(rows[r].size());
  HYPRE_IJMatrixSetRowSizes(h_->A, sizes.data());
  HYPRE_IJMatrixInitialize(h_->A);
  std::vector<HYPRE_BigInt> cols;
  std::vector<double> vals;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    cols.clear();
    vals.clear();
    for (const auto& [id, v] : rows[r]) {
      cols.push_back(static_cast<HYPRE_BigInt>(id));
      vals.push_back(v);
    }
    HYPRE_Int ncols = static_cast<HYPRE_Int>(cols.size());
    HYPRE_BigInt row = lo + static_cast<HYPRE_BigInt>(r);
    HYPRE_IJMatrixSetValues(h_->A, 1, &ncols, &row, cols.data(), vals.data());
  }
  HYPRE_IJMatrixAssemble(h_->A);
  HYPRE_IJMatrixGetObject(h_->A, reinterpret_cast<void**>(&h_->A_csr));
  for (auto* v : {&h_->b, &h_->x}) {
    HYPRE_IJVectorCreate(comm, lo, hi, v);
    HYPRE_IJVectorSetObjectType(*v, HYPRE_PARCSR);
    HYPRE_IJVectorInitialize(*v);
  }
  h_->ids.resize(static_cast<std::size_t>(count_));
  std::iota(h_->ids.begin(), h_->ids.end(), lo);

  HYPRE_BoomerAMGCreate(&h_->amg);
  HYPRE_BoomerAMGSetTol(h_->amg, 0.0);
  HYPRE_BoomerAMGSetMaxIter(h_->amg, 1);
  HYPRE_BoomerAMGSetPrintLevel(h_->amg, 0);
  HYPRE_ParCSRGMRESCreate(comm, &h_->gmres);
  HYPRE_ParCSRGMRESSetKDim(h_->gmres, 30);
  HYPRE_ParCSRGMRESSetTol(h_->gmres, opt_.tolerance);
  HYPRE_ParCSRGMRESSetMaxIter(h_->gmres, opt_.max_iterations);
  HYPRE_ParCSRGMRESSetPrecond(h_->gmres, HYPRE_BoomerAMGSolve, HYPRE_BoomerAMGSetup, h_->amg);
  HYPRE_ParCSRGMRESSetLogging(h_->gmres, 1);
}

IjSystem::~IjSystem() {
  if (h_->gmres) HYPRE_ParCSRGMRESDestroy(h_->gmres);
  if (h_->amg) HYPRE_BoomerAMGDestroy(h_->amg);
  HYPRE_IJVectorDestroy(h_->x);
  HYPRE_IJVectorDestroy(h_->b);
  HYPRE_IJMatrixDestroy(h_->A);
  delete h_;
}

// Whether b is finite on every rank (collective): asked only once a solve has
// failed, which every rank sees (the residual is global), to name the cause.
bool IjSystem::finite_everywhere(std::span<const double> b) const {
  double bad = 0.0;
  for (const double v : b) bad += 0.0 * v;  // NaN where any value is not finite
  int broken = bad == 0.0 ? 0 : 1;
  MPI_Allreduce(MPI_IN_PLACE, &broken, 1, MPI_INT, MPI_MAX, comm_);
  return broken == 0;
}

void IjSystem::solve(std::span<const double> b, std::span<double> x) {
  const auto n = static_cast<HYPRE_Int>(count_);
  HYPRE_IJVectorSetValues(h_->b, n, h_->ids.data(), b.data());
  HYPRE_IJVectorSetValues(h_->x, n, h_->ids.data(), x.data());
  HYPRE_IJVectorAssemble(h_->b);
  HYPRE_IJVectorAssemble(h_->x);
  HYPRE_ParVector bv = nullptr, xv = nullptr;
  HYPRE_IJVectorGetObject(h_->b, reinterpret_cast<void**>(&bv));
  HYPRE_IJVectorGetObject(h_->x, reinterpret_cast<void**>(&xv));
  if (!h_->ready) HYPRE_ParCSRGMRESSetup(h_->gmres, h_->A_csr, bv, xv);
  h_->ready = true;
  HYPRE_ParCSRGMRESSolve(h_->gmres, h_->A_csr, bv, xv);
  HYPRE_Int its = 0;
  HYPRE_ParCSRGMRESGetNumIterations(h_->gmres, &its);
  HYPRE_ParCSRGMRESGetFinalRelativeResidualNorm(h_->gmres, &residual_);
  iterations_ = static_cast<int>(its);
  HYPRE_IJVectorGetValues(h_->x, n, h_->ids.data(), x.data());
  // GMRES stops on its recursive residual; the true one may sit a little
  // above the tolerance at round-off (1.1e-12 against 1e-12 seen): accepted
  // within 10 times it when the solver stopped by itself.
  const bool stalled = iterations_ < opt_.max_iterations && residual_ <= 10.0 * opt_.tolerance;
  if (!(residual_ <= opt_.tolerance) && !stalled && !finite_everywhere(b))
    throw std::runtime_error(
        fmt::format("refinement: the {} has a right-hand side that is not finite (the flow "
                    "is blowing up); lower fluid.fv.cfl or fluid.fv.max_step",
                    opt_.name));
  if (!(residual_ <= opt_.tolerance) && !stalled)
    throw std::runtime_error(
        fmt::format("refinement: the {} stopped at relative residual {:.2e} after {} iterations (tolerance "
                    "{:.0e}); raise "
                    "fluid.fv.max_iterations, or lower fluid.fv.cfl if the flow is blowing up",
                    opt_.name, residual_, iterations_, opt_.tolerance));
}

}  // namespace coflow::fluid::fv::amr
