// The particles' side of the coupling with the immersed component. Each
// window the particle states go out, routed to the immersed ranks whose grid
// block (or ghost layer) they cover, and
// - psm: the hydrodynamic force and torque on each particle come back, held
//   constant over the window's sub-steps;
// - point: the fluid at each particle comes back instead (one copy per
//   particle), and after the sub-steps each particle's impulse of the fluid
//   forces goes out for the momentum source (seed 003 eq. 3.43).
// serial-explicit: the loads of this window's states act before the sub-steps.
// parallel-explicit (psm): the particles sub-cycle on the previous window's
// loads while the immersed side and the fluid compute this window's; those
// arrive after the sub-steps, are matched to the particles by id (a particle
// may have moved to another rank meanwhile) and act in the next window; the
// loads in flight belong to a checkpoint. The next window's states go out right
// after the sub-steps, before this window's loads come in, so that the immersed
// side covers them while the fluid still steps (two point exchanges
// alternate, window by window: each remembers its own routing).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "coflow/exchange.hpp"
#include "coflow/session.hpp"
#include "particles/particles_interface.hpp"

namespace coflow::particles {

class ImmersedLink {
 public:
  ImmersedLink(coupler::Session& s, ParticleSolver& solver, const ParticleParams& params);
  void before_step(long w);
  void after_step(long w);
  void save(const std::string& dir);  // collective
  void load(const std::string& dir);  // the loads in flight of a parallel-explicit checkpoint

 private:
  void send_states(int k);
  std::vector<double> receive_loads(int k);
  void apply_loads(const std::vector<double>& rows);
  void receive_fluid();
  void send_impulses();

  coupler::Session& s_;
  ParticleSolver& solver_;
  std::vector<double> contact_angle_;  // per species, degrees (-1: the fluid's)
  bool point_ = false, lagged_ = false;
  bool warned_fast_ = false;  // point: the warning on particles crossing cells in a window was given
  void check_crossing();
  bool ahead_ = false;  // lagged: this window's states went out after the last one's sub-steps
  std::unique_ptr<coupler::PointExchange> to_immersed_[2], impulse_out_;
  std::vector<std::byte> records_, loads_, fluid_bytes_, impulse_records_;
  std::vector<std::array<double, 3>> positions_;
  std::vector<DepartedImpulse> departed_;  // left through an outlet this window
  std::vector<double> hforce_, htorque_, samples_, impulse_, pending_;
  std::vector<std::int64_t> sent_ids_[2];
};

}  // namespace coflow::particles
