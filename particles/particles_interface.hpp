// The particles component's interface. Variants register in particles/variants.cpp.
#pragma once

#include <mpi.h>

#include "coflow/decomposition.hpp"
#include "coflow/run_config.hpp"

namespace coflow::particles {

class ParticleSolver {
 public:
  struct Setup {
    const config::Config& cfg;
    coupler::Decomposition decomposition;
    int rank = 0;
    MPI_Comm comm = MPI_COMM_NULL;
  };
  virtual ~ParticleSolver() = default;
};

}  // namespace coflow::particles
