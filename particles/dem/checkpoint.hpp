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

// The event counters of series/particles.csv: collisions and wall collisions
// since the last series row, failed bonds since the start.
struct EventCounts {
  long collisions = 0, wall_collisions = 0, broken_bonds = 0;
};

// Collective. counts: this rank's; the checkpoint keeps their sums
// (counters.h5), so that the rows after a restart count what a straight run's
// do even when the checkpoint falls between two rows.
void save_state(MPI_Comm comm, const std::string& dir, double time, long steps, const ParticleArrays& p,
                const std::vector<SavedContact>& contacts, const EventCounts& counts = {});
// counts (when given): the sums saved; 0 for those a checkpoint lacks (one
// written before they were kept).
void load_state(const std::string& dir, const ParticleParams& params, ParticleArrays& p,
                std::vector<SavedContact>& contacts, EventCounts* counts = nullptr);

}  // namespace coflow::particles::dem
