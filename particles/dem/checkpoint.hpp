// DEM checkpoints: particles, contact histories and the count of failed bonds,
// in three HDF5 files written with the output layer (particles.h5, contacts.h5,
// counters.h5).
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
  std::array<double, 3> normal{};  // mesh walls: the contact's direction (mesh_history_slot)
  bool wall() const { return b < 0; }
  std::int64_t wall_face() const { return -1 - b; }
  static SavedContact from(std::int64_t a, std::int64_t b, const ContactState& s) {
    return {a, b, {s.shear[0], s.shear[1], s.shear[2]}, s.bonded, {s.normal[0], s.normal[1], s.normal[2]}};
  }
  ContactState state() const {
    ContactState s;
    s.shear = V3(shear[0], shear[1], shear[2]);
    s.bonded = bonded;
    s.normal = V3(normal[0], normal[1], normal[2]);
    return s;
  }
};

// Collective. broken_bonds: this rank's count of failed bonds since the start;
// the checkpoint keeps their sum (counters.h5).
void save_state(MPI_Comm comm, const std::string& dir, double time, long steps, const ParticleArrays& p,
                const std::vector<SavedContact>& contacts, long broken_bonds = 0);
// broken_bonds (when given): the sum saved, 0 from a checkpoint without one.
void load_state(const std::string& dir, const ParticleParams& params, ParticleArrays& p,
                std::vector<SavedContact>& contacts, long* broken_bonds = nullptr);

}  // namespace coflow::particles::dem
