// The immersed component's interface. Variants register in immersed/variants.cpp.
#pragma once

#include <mpi.h>

#include "coflow/decomposition.hpp"
#include "coflow/run_config.hpp"

namespace coflow::immersed {

class ImmersedMethod {
 public:
  struct Setup {
    const config::Config& cfg;
    coupler::Decomposition decomposition;
    int rank = 0;
    MPI_Comm comm = MPI_COMM_NULL;
  };
  virtual ~ImmersedMethod() = default;
};

}  // namespace coflow::immersed
