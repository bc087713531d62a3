#include "particles/dpm_reference/dpm_reference.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>
#include <tuple>

#include "coflow/log.hpp"
#include "coflow/output.hpp"
#include "particles/dem/checkpoint.hpp"
#include "particles/dem/initial.hpp"
#include "particles/dpm/state.hpp"

namespace coflow::particles {

using dpm::V3;

DpmReference::DpmReference(const Setup& setup, const Params&) : params_(setup.params) {
  int size = 1;
  MPI_Comm_size(setup.comm, &size);
  if (size != 1) throw std::runtime_error("dpm-reference is serial: set particles.ranks: 1");
  s_ = dpm::make_setup(setup.params, setup.cfg);
  wall_impulse_.reset(s_.meshes.size());
  s_.mesh_all_triangles = true;  // the oracle tests every triangle
  const ParticleArrays a = dem::make_initial(setup.params, setup.cfg);
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double D = 2.0 * a.radius[i];
    p_.push_back({a.id[i], a.species[i], V3(&a.x[3 * i]), V3(&a.v[3 * i]), V3(&a.w[3 * i]), D, a.mass[i],
                  a.inertia[i], params_.species.at(a.species[i]).second.density, s_.still, V3::Zero(), V3::Zero()});
  }
  inlets_ = dpm::make_inlets(setup.params, s_.cell, s_.lower, dpm::periods(s_));
  for (const auto& p : p_) next_id_ = std::max(next_id_, p.id + 1);
  dt_ = s_.auto_step ? stable_step() : s_.dt;
  log::info("dpm-reference: {} particles, step {:.4g} s ({}), fluid {}", p_.size(), dt_,
            s_.auto_step ? "eq. 4.15 at the start" : "given",
            s_.still.mu > 0 ? fmt::format("at rest, rho {:.4g} kg/m^3, mu {:.4g} Pa s", s_.still.rho, s_.still.mu)
                            : std::string("none (vacuum)"));
}

double DpmReference::stable_step() const {
  double dt = std::numeric_limits<double>::infinity();
  for (const auto& p : p_) dt = std::min(dt, dpm::lagrangian_step(s_, p.D, p.rho_p, p.v, p.fluid));
  if (s_.collisions)  // the mean time between collisions, tau_c of eq. 4.15
    dt = std::min(dt, 0.2 * dpm::mean_collision_time(
                               p_.size(), [&](std::size_t i) { return p_[i].x; }, [&](std::size_t i) { return p_[i].v; },
                               [&](std::size_t i) { return p_[i].D; }, s_));
  return std::isfinite(dt) ? dt : 1.0;  // nothing limits it: the window decides
}

// 2. Collisions along the straight trajectories x + u t, t in [0, h), with u
//    the mean velocity of the step (eqs 4.23-4.28), every pair and every wall
//    face tested.
std::vector<dpm::Event> DpmReference::find_events(double h, const std::vector<V3>& u) const {
  std::vector<dpm::Event> events;
  if (s_.collisions)
    for (std::size_t i = 0; i < p_.size(); ++i)
      for (std::size_t j = i + 1; j < p_.size(); ++j) {
        const V3 d = dpm::min_image(p_[i].x - p_[j].x, s_);
        const double t = dpm::contact_time(d, u[i] - u[j], 0.5 * (p_[i].D + p_[j].D), h);
        if (std::isfinite(t))
          events.push_back({t, std::min(p_[i].id, p_[j].id), std::max(p_[i].id, p_[j].id), i, j});
      }
  std::vector<int> scratch;
  for (std::size_t i = 0; i < p_.size(); ++i) {
    dpm::wall_events(p_[i].x, u[i], p_[i].D, p_[i].id, i, h, s_, events);
    dpm::mesh_events(p_[i].x, u[i], p_[i].D, p_[i].id, i, h, s_, scratch, events);  // every triangle
  }
  return events;
}

// Events are taken earliest first (ties by particle ids); a particle takes
// one event here (binary collisions: the step is a fraction of the mean time
// between collisions, eq. 4.15), and only walls after it (dpm::finish_step in
// step()). Returns each particle's collision time (-1: none).
std::vector<double> DpmReference::collide(const std::vector<dpm::Event>& events, const std::vector<V3>& u,
                                          std::vector<dpm::Motion>& next) {
  std::vector<double> hit(p_.size(), -1.0);  // collision time, -1: none
  for (const dpm::Event& e : events) {
    if (hit[e.i] >= 0.0 || (e.b >= 0 && hit[e.j] >= 0.0)) continue;
    Particle& a = p_[e.i];
    if (e.b < 0) {
      V3 n, point;
      const dpm::Restitution* law = nullptr;
      dpm::wall_contact(e.b, a.x, u[e.i], e.t, a.D, s_, n, point, law);
      const V3 before = next[e.i].v;
      if (dpm::collide_wall(next[e.i].v, next[e.i].w, a.D, n, *law)) {  // only applied impulses count
        wall_impulse_.add(dpm::wall_slot(e.b), V3(-a.m * (next[e.i].v - before)));
        if (!dpm::mirror_event(e.b, s_)) {  // a symmetry face's mirror is no wall collision
          events_.impact(time_ + e.t, a.id, -1 - e.b, point, n, before);
          ++wall_collisions_;
        }
      }
      hit[e.i] = e.t;
      continue;
    }
    Particle& b = p_[e.j];
    const V3 d = dpm::min_image((a.x + u[e.i] * e.t) - (b.x + u[e.j] * e.t), s_);
    const V3 n = -d.normalized();  // from a to b
    const V3 relative = next[e.i].v - next[e.j].v;
    if (dpm::collide_pair(next[e.i].v, next[e.i].w, a.m, a.D, next[e.j].v, next[e.j].w, b.m, b.D, n,
                          s_.pair_law(a.species, b.species))) {  // only applied impulses count
      events_.collision(time_ + e.t, a.id, b.id, -n, relative);
      ++collisions_;
    }
    hit[e.i] = hit[e.j] = e.t;
  }
  return hit;
}

// 5. Inlets: the particles that entered during the step (injection.hpp),
//    with the fluid at their inlet's probes.
void DpmReference::inject_at_inlets(double h) {
  for (std::size_t k = 0; k < inlets_.size(); ++k) {
    std::vector<std::pair<V3, double>> nearby;
    for (const Particle& p : p_)
      if (dpm::near_inlet(inlets_[k], h, p.x, p.D)) nearby.emplace_back(p.x, p.D);
    std::vector<dpm::Entering> entering;
    dpm::inject(inlets_[k], static_cast<int>(k), s_.dispersion.seed, time_, h, nearby, entering);
    for (const dpm::Entering& e : entering) {
      const double rho_p = inlets_[k].density, m = rho_p * std::numbers::pi * e.D * e.D * e.D / 6.0;
      p_.push_back({next_id_++, e.species, e.x, e.v, V3::Zero(), e.D, m, 0.1 * m * e.D * e.D, rho_p,
                    probe_fluid_.at(inlets_, k, e.entry, s_.still), V3::Zero(), V3::Zero()});
    }
  }
}

void DpmReference::step(double h) {
  // 1. Fluid forces and gravity, classical RK4 (seed 003 eqs 4.12-4.14); the
  //    fluid at the particle is held over the step.
  //    With dispersion the fluid seen is the mean plus the Langevin fluctuation.
  std::vector<dpm::Motion> next(p_.size());
  std::vector<dpm::FluidSample> seen(p_.size());
  for (std::size_t i = 0; i < p_.size(); ++i) {
    Particle& p = p_[i];
    seen[i] = p.fluid;
    if (s_.dispersion.on) {
      dpm::langevin_step(p.uprime, p.turbulent, p.fluid, p.v, h, s_.dispersion, p.id, steps_);
      seen[i].u += p.uprime;
    }
    next[i] = dpm::rk4({p.x, p.v, p.w}, p.D, p.m, p.I, p.rho_p, seen[i], s_, h);
    ranges_.note(p.species, next[i].beyond);
  }
  // 2. Collisions along the straight trajectories (find_events, collide).
  std::vector<V3> u(p_.size());
  for (std::size_t i = 0; i < p_.size(); ++i) u[i] = (next[i].x - p_[i].x) / h;
  std::vector<dpm::Event> events = find_events(h, u);
  std::sort(events.begin(), events.end());
  const std::vector<double> hit = collide(events, u, next);
  // 3. New states: after a collision the particle continues from the contact
  //    point with its new velocity (eqs 4.30-4.31).
  std::vector<V3> last(p_.size());  // the positions before the step
  std::vector<int> scratch;
  for (std::size_t i = 0; i < p_.size(); ++i) {
    Particle& p = p_[i];
    last[i] = p.x;
    if (hit[i] < 0.0) {
      p.x = next[i].x;
    } else {  // walls and meshes on the rest of the path take it too (setup.hpp)
      const double t = hit[i];
      p.x = dpm::finish_step(p.x + u[i] * t, next[i].v, next[i].w, h - t, p.D, p.id, s_, scratch,
                             [&](double dt, std::int64_t b, const V3& point, const V3& n, const V3& before) {
                               wall_impulse_.add(dpm::wall_slot(b), V3(-p.m * (next[i].v - before)));
                               if (dpm::mirror_event(b, s_)) return;
                               events_.impact(time_ + t + dt, p.id, -1 - b, point, n, before);
                               ++wall_collisions_;
                             });
    }
    p.v = next[i].v;
    p.w = next[i].w;
    p.impulse += next[i].impulse;
    p.last_force = dpm::fluid_load(seen[i], p.D, p.v, p.w, s_.forces).force();
  }
  // 4. Faces: periodic wrap, outlets remove (the fluid takes a removed
  //    particle's impulse back where it was last inside).
  std::vector<Particle> kept;
  kept.reserve(p_.size());
  for (std::size_t i = 0; i < p_.size(); ++i) {
    Particle& p = p_[i];
    if (dpm::apply_faces(p.x, s_))
      kept.push_back(p);
    else
      departed_.push_back(
          {p.id, {last[i][0], last[i][1], last[i][2]}, {p.impulse[0], p.impulse[1], p.impulse[2]}});
  }
  p_.swap(kept);
  inject_at_inlets(h);
  time_ += h;
  ++steps_;
}

void DpmReference::advance(double dt, long substeps) {
  const double h = dt / substeps;
  departed_.clear();  // those of the last window, if nobody took them
  for (long n = 0; n < substeps; ++n) {
    // Sub-steps of the Lagrangian step of eq. 4.15 when it is shorter.
    const long k = s_.auto_step ? dpm::lagrangian_substeps(s_, h, stable_step()) : 1;  // eq. 4.15 only when automatic
    for (long m = 0; m < k; ++m) step(h / k);
  }
  ranges_.report(MPI_COMM_SELF, s_.species_names);
}

const ParticleArrays& DpmReference::particles() const {
  view_ = ParticleArrays{};
  for (const auto& p : p_) {
    view_.id.push_back(p.id);
    view_.species.push_back(p.species);
    for (int k = 0; k < 3; ++k) {
      view_.x.push_back(p.x[k]);
      view_.v.push_back(p.v[k]);
      view_.w.push_back(p.w[k]);
      view_.force.push_back(p.last_force[k]);
    }
    view_.radius.push_back(0.5 * p.D);
    view_.mass.push_back(p.m);
    view_.inertia.push_back(p.I);
  }
  return view_;
}

void DpmReference::set_hydrodynamic(std::span<const double>, std::span<const double>) {
  throw std::runtime_error("dpm-reference takes the fluid at the particles (immersed.method: point), not forces");
}

void DpmReference::set_fluid(std::span<const double> samples) {
  if (samples.size() < kFluidValues * p_.size())
    throw std::runtime_error(
        "the fluid sent fewer samples than there are particles (a coupling protocol mismatch)");
  for (std::size_t i = 0; i < p_.size(); ++i) p_[i].fluid = dpm::fluid_sample(&samples[kFluidValues * i]);
  probe_fluid_.set(samples.subspan(kFluidValues * p_.size()), dpm::ProbeFluid::count(inlets_));
}

std::vector<std::array<double, 3>> DpmReference::probe_points() const {
  return dpm::ProbeFluid::points(inlets_);
}

void DpmReference::take_departed(std::vector<DepartedImpulse>& departed) {
  departed.swap(departed_);
  departed_.clear();
}

void DpmReference::take_impulse(std::vector<double>& impulse) {
  impulse.clear();
  for (auto& p : p_) {
    impulse.insert(impulse.end(), {p.impulse[0], p.impulse[1], p.impulse[2]});
    p.impulse = V3::Zero();
  }
}

ParticleStats DpmReference::stats() {
  ParticleStats st;
  st.count = static_cast<long>(p_.size());
  for (const auto& p : p_) {
    for (int k = 0; k < 3; ++k) st.momentum[k] += p.m * p.v[k];
    st.kinetic_energy += 0.5 * p.m * p.v.squaredNorm();
    st.rotational_energy += 0.5 * p.I * p.w.squaredNorm();
  }
  st.collisions = collisions_;
  st.wall_collisions = wall_collisions_;
  collisions_ = wall_collisions_ = 0;
  return st;
}

void DpmReference::save(const std::string& dir) {
  const ParticleArrays& a = particles();
  dem::save_state(MPI_COMM_SELF, dir, time_, steps_, a, {}, {collisions_, wall_collisions_, 0});
  std::map<std::int64_t, dpm::Fluctuation> up;
  for (const auto& p : p_)
    if (p.turbulent) up[p.id] = {p.uprime, true};
  dpm::save_extra(dir, time_, next_id_, inlets_, up);
}

void DpmReference::load(const std::string& dir, long steps, double time) {
  time_ = time;  // dpm.csv holds the exact clock
  ParticleArrays a;
  std::vector<dem::SavedContact> contacts;
  dem::EventCounts counts;
  dem::load_state(dir, params_, a, contacts, &counts);
  collisions_ = counts.collisions;
  wall_collisions_ = counts.wall_collisions;
  p_.clear();
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double D = 2.0 * a.radius[i];
    p_.push_back({a.id[i], a.species[i], V3(&a.x[3 * i]), V3(&a.v[3 * i]), V3(&a.w[3 * i]), D, a.mass[i],
                  a.inertia[i], params_.species.at(a.species[i]).second.density, s_.still, V3(&a.force[3 * i]), V3::Zero()});
  }
  // In id order, as a straight run holds them (a checkpoint of several ranks
  // lists rank 0's particles first): eq. 3.47's sums go in the same order.
  std::sort(p_.begin(), p_.end(), [](const Particle& l, const Particle& r) { return l.id < r.id; });
  for (const auto& p : p_) next_id_ = std::max(next_id_, p.id + 1);
  std::map<std::int64_t, dpm::Fluctuation> up;
  dpm::load_extra(dir, time_, next_id_, inlets_, up);
  for (auto& p : p_)
    if (const auto it = up.find(p.id); it != up.end()) {
      p.uprime = it->second.u;
      p.turbulent = it->second.started;
    }
  // The steps taken, as the checkpoint counted them: the windows' sub-steps
  // and eq. 4.15's extra ones (the Langevin draws are keyed by the count, as
  // in dpm: one from the windows alone would draw used numbers again).
  const long saved = coflow::output::read_step(dir + "/particles.h5");
  steps_ = saved >= 0 ? saved : steps;
}

}  // namespace coflow::particles
