// DEM checkpoints: particles and contact histories, in two HDF5 files written
// with the output layer (particles.h5, contacts.h5).
#pragma once

#include <mpi.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "particles/dem/contact.hpp"
#include "particles/particles_interface.hpp"

namespace coflow::particles::dem {

struct SavedContact {
  std::int64_t a = 0;  // particle id
  std::int64_t b = 0;  // partner id, or -1 - face for a wall
  std::array<double, 3> shear{};
  bool bonded = false;
  bool wall() const { return b < 0; }
  std::int64_t wall_face() const { return -1 - b; }
  ContactState state() const {
    ContactState s;
    s.shear = V3(shear[0], shear[1], shear[2]);
    s.bonded = bonded;
    return s;
  }
};

void save_state(MPI_Comm comm, const std::string& dir, double time, long steps, const ParticleArrays& p,
                const std::vector<SavedContact>& contacts);
void load_state(const std::string& dir, const ParticleParams& params, ParticleArrays& p,
                std::vector<SavedContact>& contacts);

}  // namespace coflow::particles::dem
