// A sparse linear system with rows given as stencils of global ids (each rank
// its contiguous range of rows), solved by hypre's GMRES preconditioned by
// one BoomerAMG V-cycle (algebraic multigrid: the composite grid's operator
// has no structured stencil). Debian's libhypre-dev, as StructSystem.
#pragma once

#include <mpi.h>

#include <span>
#include <string>
#include <vector>

#include "fluid/fv/amr/composite_grid.hpp"

namespace coflow::fluid::fv::amr {

class IjSystem {
 public:
  struct Options {
    double tolerance = 1e-12;  // relative residual, 2-norm
    int max_iterations = 200;
    std::string name = "composite Poisson solve";  // for messages
  };
  // Rows first_row .. first_row + rows.size() - 1 of the global matrix.
  IjSystem(MPI_Comm comm, long first_row, const std::vector<Stencil>& rows, Options opt);
  ~IjSystem();
  IjSystem(const IjSystem&) = delete;
  IjSystem& operator=(const IjSystem&) = delete;

  // Solves A x = b (local rows), x holding the initial guess. Throws when
  // the tolerance is not reached.
  void solve(std::span<const double> b, std::span<double> x);
  int last_iterations() const { return iterations_; }
  double last_residual() const { return residual_; }

 private:
  struct Hypre;
  bool finite_everywhere(std::span<const double> b) const;
  Hypre* h_ = nullptr;
  MPI_Comm comm_;
  Options opt_;
  long first_ = 0, count_ = 0;
  int iterations_ = 0;
  double residual_ = 0.0;
};

}  // namespace coflow::fluid::fv::amr
