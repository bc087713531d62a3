// The event logs of a particle run (events/collisions.csv, bonds.csv,
// impacts.csv): each rank's events of a window, gathered on rank 0 and written
// in (time, i, j) order, so that the files do not depend on the rank count.
#pragma once

#include <fstream>
#include <string>

#include "coflow/run_config.hpp"
#include "coflow/session.hpp"
#include "particles/particles_interface.hpp"

namespace coflow::particles {

class EventLog {
 public:
  // Opens the files the output asks for; a restart (w0 > 0) appends.
  EventLog(coupler::Session& s, const config::OutputParams& out, bool point_particles, long w0);
  bool wanted() const { return collisions_ || bonds_; }
  // Collective: write one window's events.
  void write(const ParticleEvents& ev);
  // Checkpoint: the files' sizes in dir/events.txt (rank 0), to which a
  // restart into this directory cuts them back (launcher/restart.cpp).
  void save(const std::string& dir) const;

 private:
  void write_impacts(const ParticleEvents& ev);
  void write_pairs(const ParticleEvents& ev);

  coupler::Session& s_;
  bool collisions_ = false, bonds_ = false, impacts_ = false;
  std::ofstream collisions_csv_, bonds_csv_, impacts_csv_;
};

}  // namespace coflow::particles
