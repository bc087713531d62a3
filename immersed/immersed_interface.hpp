// The immersed component's interface. Variants register in immersed/variants.cpp.
#pragma once

#include <mpi.h>

#include "coflow/decomposition.hpp"
#include "coflow/run_config.hpp"

namespace coflow::coupler {
class Session;
}

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
  // The whole coupled run: each method has its own exchanges per window
  // (ARCHITECTURE.md, "Data per coupling window").
  virtual void run(coupler::Session& s) = 0;
};

}  // namespace coflow::immersed
