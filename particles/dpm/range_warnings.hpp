// Warnings, once per run and species, for force correlations used beyond the
// range of Reynolds numbers their authors fitted them on (forces.hpp, Beyond):
// the run goes on, extrapolating, and says so.
#pragma once

#include <mpi.h>

#include <string>
#include <vector>

#include "coflow/log.hpp"
#include "particles/dpm/forces.hpp"

namespace coflow::particles::dpm {

class RangeWarnings {
 public:
  void note(int species, unsigned beyond) {
    if (beyond == 0) return;
    if (seen_.size() <= static_cast<std::size_t>(species)) seen_.resize(static_cast<std::size_t>(species) + 1, 0u);
    seen_[static_cast<std::size_t>(species)] |= beyond;
  }
  // Collective over comm: rank 0 warns about each (species, correlation) seen
  // on any rank for the first time.
  void report(MPI_Comm comm, const std::vector<std::string>& species) {
    seen_.resize(species.size(), 0u);
    warned_.resize(species.size(), 0u);
    std::vector<unsigned> all(species.size(), 0u);
    MPI_Allreduce(seen_.data(), all.data(), static_cast<int>(all.size()), MPI_UNSIGNED, MPI_BOR, comm);
    int rank = 0;
    MPI_Comm_rank(comm, &rank);
    for (std::size_t k = 0; k < species.size(); ++k) {
      const unsigned fresh = all[k] & ~warned_[k];
      warned_[k] |= all[k];
      if (rank != 0 || fresh == 0) continue;
      if (fresh & kSaffmanBeta)
        log::warn("dpm: species '{}': Saffman lift with Mei's correction (seed 003 eq. 3.32) used outside "
                  "0.005 <= beta <= 0.4, the range Mei (1992) fitted; extrapolated", species[k]);
      if (fresh & kMagnusReP)
        log::warn("dpm: species '{}': Magnus lift of Oesterle & Dinh (seed 003 eq. 3.33) used beyond Re_p 140, the "
                  "range they measured; extrapolated", species[k]);
      if (fresh & kRotationReR)
        log::warn("dpm: species '{}': rotational coefficient of Dennis et al. (seed 003 eq. 3.34) used beyond Re_r "
                  "1000, the range they computed; extrapolated", species[k]);
    }
  }

 private:
  std::vector<unsigned> seen_, warned_;
};

}  // namespace coflow::particles::dpm
