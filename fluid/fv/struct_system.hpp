// A symmetric positive (semi-)definite 5-point (2D) or 7-point (3D) system on
// the fluid grid's cells, distributed as the fluid's blocks, solved by
// hypre's Struct conjugate gradients preconditioned by one multigrid V-cycle
// (PFMG or SMG), or by conjugate gradients preconditioned by the diagonal,
// written out here with hypre's exchange of ghost cells (use_diagonal). fv's
// pressure Poisson, implicit viscous and k-epsilon solves are such systems;
// hypre is Debian's libhypre-dev.
#pragma once

#include <mpi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "coflow/decomposition.hpp"

namespace coflow::fluid::fv {

class StructSystem {
 public:
  struct Options {
    std::string multigrid = "pfmg";  // pfmg | smg
    double tolerance = 1e-10;        // relative residual, 2-norm
    int max_iterations = 200;
    std::string name = "system";  // for messages
  };
  // The owned box of this rank in a grid of `cells` (one cell along z: 2D).
  StructSystem(MPI_Comm comm, const coupler::Box& owned, const coupler::Index3& cells,
               const std::array<bool, 3>& periodic, Options opt);
  ~StructSystem();
  StructSystem(const StructSystem&) = delete;
  StructSystem& operator=(const StructSystem&) = delete;

  // The matrix, per owned cell (x fastest): its diagonal and its coupling to
  // the cells one below and one above along x, y, z (zero across a wall). The
  // caller keeps it symmetric: a cell's upper coupling is the next one's lower.
  using Couplings = std::array<std::span<const double>, 3>;
  void set(std::span<const double> diag, const Couplings& lower, const Couplings& upper);
  // Solve A x = b, x holding the initial guess (owned cells, x fastest).
  // Throws when the tolerance is not reached within max_iterations, or when
  // the conjugate gradients break down short of it (judge_early_stop).
  void solve(std::span<const double> b, std::span<double> x);
  // Precondition by the diagonal alone (Jacobi) instead of the multigrid: for
  // a system dominated by its diagonal (a viscous solve with a short step),
  // where a V-cycle costs more than the iterations it saves. These solves
  // run coflow's own loops (solve_diagonal), not hypre's PCG.
  void use_diagonal(bool on);
  // One multigrid V-cycle from a zero guess, x = M b, without the conjugate
  // gradients: the coarsest-level solve of a multigrid of coflow's own
  // (PoissonMultigrid), where it must be a fixed linear map.
  void cycle(std::span<const double> b, std::span<double> x);
  int last_iterations() const { return iterations_; }
  // Also stop when the residual's 2-norm is below `floor` (0: no floor): a
  // right-hand side of round-off size cannot be reduced by the relative
  // tolerance.
  void set_absolute_floor(double floor);

  // A matrix being assembled: per owned cell its diagonal and its couplings
  // below and above along each axis (zero until set); set() hands it over.
  struct Rows {
    explicit Rows(std::size_t cells = 0) { reset(cells); }
    // Room for `cells` rows, the entries left as they are (for an assembly
    // that writes every entry: a matrix rebuilt every step).
    void resize(std::size_t cells) {
      diag.resize(cells);
      for (auto& v : lower) v.resize(cells);
      for (auto& v : upper) v.resize(cells);
    }
    // All entries zero again, the storage kept.
    void reset(std::size_t cells) {
      diag.assign(cells, 0.0);
      for (auto& v : lower) v.assign(cells, 0.0);
      for (auto& v : upper) v.assign(cells, 0.0);
    }
    std::vector<double> diag;
    std::array<std::vector<double>, 3> lower, upper;
  };
  void set(const Rows& r) {
    set(r.diag, {r.lower[0], r.lower[1], r.lower[2]}, {r.upper[0], r.upper[1], r.upper[2]});
  }
  // As set(r), but the matrix is handed over without a copy: `r` comes back
  // holding the storage of the previous matrix (entries unspecified; empty
  // after the first). For a matrix rebuilt every step.
  void take(Rows& r);
  double last_residual() const { return residual_; }

 private:
  void make_solver();
  void changed();
  void sync_hypre();
  void solve_diagonal(std::span<const double> b, std::span<double> x);
  struct Residual {
    double rr = 0.0, bb = 0.0;  // |b - A x|^2, |b|^2
    double relative = 0.0, backward = 0.0;
    bool within(double tolerance, double floor) const {
      return std::isfinite(rr) && rr <= std::max(tolerance * tolerance * bb, floor * floor);
    }
  };
  void judge_early_stop(std::span<const double> b, std::span<const double> x);
  Residual true_residual(std::span<const double> b, std::span<const double> x);
  double matvec(const double* p, std::vector<double>& s);  // s = A p; returns p . s on this rank
  long row_asymmetries(long j) const;
  void free_solver();
  struct Hypre;
  Hypre* h_ = nullptr;
  Options opt_;
  int dims_ = 3;
  bool diagonal_ = false;
  bool red_black_ = true;  // PFMG smooths by red-black Gauss-Seidel (else weighted Jacobi)
  // The matrix (owned cells, x fastest). hypre gets a copy only when its
  // multigrid is used (stale_: not yet copied); the diagonal PCG reads it
  // here, 1 / a_ii in inv_diag_ (inv_stale_: not yet computed).
  Rows rows_;
  std::vector<double> inv_diag_;
  bool stale_ = false, inv_stale_ = false;
  // Every coupling to a lower neighbour in this rank's block equals that
  // neighbour's coupling back, to the bit (sym_stale_: not yet checked):
  // matvec then reads the lower couplings from the upper ones.
  bool symmetric_ = false, sym_stale_ = false;
  int iterations_ = 0;
  double residual_ = 0.0;
  double floor_ = 0.0;
  bool warned_ = false;  // an early stop at the rounding limit was logged
};

// The message of a linear solve of fv that stopped short of its tolerance.
std::string not_converged(const std::string& name, double residual, long iterations, double tolerance);
// The message of a solve whose right-hand side is not finite (|b|^2 = bb).
std::string rhs_not_finite(const std::string& name, double bb);

}  // namespace coflow::fluid::fv
