#include "particles/dem_reference/dem_reference.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <tuple>

#include "coflow/log.hpp"
#include "coflow/output.hpp"
#include "particles/dem/checkpoint.hpp"

namespace coflow::particles {

using dem::V3;

DemReference::DemReference(const Setup& setup, const Params&) : comm_(setup.comm), params_(setup.params) {
  int size = 1;
  MPI_Comm_size(setup.comm, &size);
  if (size != 1) throw std::runtime_error("dem-reference is serial: set particles.ranks: 1");
  const ParticleArrays a = dem::make_initial(setup.params, setup.cfg);
  s_ = dem::make_setup(setup.params, setup.cfg, a);
  wall_impulse_.reset(s_.meshes.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    p_.push_back({a.id[i], a.species[i], V3(&a.x[3 * i]), V3(&a.v[3 * i]), V3(&a.w[3 * i]), a.radius[i], a.mass[i],
                  a.inertia[i], V3::Zero(), V3::Zero(), V3::Zero(), V3::Zero()});
  // Cement the pairs that touch (within the gap) at the start.
  if (!s_.bond_file.empty())
    for (const auto& pair : dem::bonds_from_file(a, s_)) contacts_[pair].bonded = true;
  else if (s_.bond_gap >= 0)
    for (std::size_t i = 0; i < p_.size(); ++i)
      for (std::size_t j = i + 1; j < p_.size(); ++j)
        if (dem::min_image(p_[i].x - p_[j].x, s_).norm() - p_[i].r - p_[j].r <= s_.bond_gap)
          contacts_[{p_[i].id, p_[j].id}].bonded = true;
  log::info("dem-reference: {} particles, {} bonds, step {:.4g} s", p_.size(), contacts_.size(), s_.dt);
}

// Particle pairs, seed 000 eqs 2.11-2.18; the grains whose bond failed in
// compression go to `crushed`.
void DemReference::pair_forces(double h, std::vector<std::size_t>& crushed) {
  for (std::size_t i = 0; i < p_.size(); ++i)
    for (std::size_t j = i + 1; j < p_.size(); ++j) {
      Particle& a = p_[i];
      Particle& b = p_[j];
      const V3 d = dem::min_image(a.x - b.x, s_);
      const double dist = d.norm();
      const double overlap = a.r + b.r - dist;
      const auto key = std::make_pair(a.id, b.id);
      auto it = contacts_.find(key);
      if (overlap <= 0.0 && (it == contacts_.end() || !it->second.bonded)) {
        if (it != contacts_.end()) contacts_.erase(it);
        continue;
      }
      if (it == contacts_.end()) {
        it = contacts_.emplace(key, dem::ContactState{}).first;
        ++collisions_;
        events_.collision(time_, a.id, b.id, d / dist, a.v - b.v);
      }
      if (dist == 0.0) dem::coincident_centres(a.id, b.id, time_);  // (NaN: the state check's)
      const V3 n = d / dist;
      const double a1 = a.r - 0.5 * overlap, a2 = b.r - 0.5 * overlap;
      const V3 vrel = (a.v + a.w.cross(-a1 * n)) - (b.v + b.w.cross(a2 * n));
      const dem::ContactForce c = dem::contact_force(n, overlap, a1, a2, vrel, a.r + b.r, it->second, s_.law, h);
      if (c.failure != dem::Failure::none) {
        ++broken_;
        events_.bond(time_, a.id, b.id, c);
        if (c.failure == dem::Failure::compression) {
          crushed.push_back(i);
          crushed.push_back(j);
        }
      }
      if (!c.active) {
        contacts_.erase(it);
        continue;
      }
      a.F += c.force;
      b.F -= c.force;
      a.T += c.torque1;
      b.T += c.torque2;
    }
}

// Domain faces that are walls: the same law with a plane (eq. 2.13, R1 - d).
void DemReference::wall_forces(double h) {
  for (auto& a : p_)
    for (int f = 0; f < 6; ++f) {
      if (s_.faces[f] != dem::Face::wall) continue;
      const double dist = dem::face_distance(f, a.x, s_);
      const double overlap = a.r - dist;
      const auto key = std::make_pair(a.id, f);
      auto it = walls_.find(key);
      if (overlap <= 0.0) {
        if (it != walls_.end()) walls_.erase(it);
        continue;
      }
      if (it == walls_.end()) {
        it = walls_.emplace(key, dem::ContactState{}).first;
        ++wall_collisions_;
      }
      const V3 n = dem::face_normal(f);
      const V3 vrel = a.v + a.w.cross(-dist * n);
      dem::ContactLaw law = s_.law;
      law.mu = s_.wall_friction[f];
      const dem::ContactForce c = dem::contact_force(n, overlap, dist, 0.0, vrel, 2 * a.r, it->second, law, h);
      a.F += c.force;
      a.T += c.torque1;
      wall_impulse_.add(static_cast<std::size_t>(f), V3(-h * c.force));
    }
}

// Triangle meshes: every triangle is tested (no hierarchy).
void DemReference::mesh_forces(double h) {
  std::vector<dem::MeshContact> hits;
  for (auto& a : p_)
    for (std::size_t m = 0; m < s_.meshes.size(); ++m) {
      s_.meshes[m].contacts_all(a.x, a.r, hits);
      for (const auto& hit : hits) {
        const V3 d = a.x - hit.point;
        const double dist = d.norm();
        if (dist == 0.0) dem::centre_on_mesh(a.id, m, time_);
        const V3 n = d / dist;
        // One history per contact direction (so coplanar triangles act as one plane).
        const int slot = dem::mesh_history_slot(n, steps_, [&](int k) -> const dem::ContactState* {
          auto f = walls_.find({a.id, static_cast<int>(dem::mesh_wall_key(m, k))});
          return f == walls_.end() ? nullptr : &f->second;
        });
        const auto key = std::make_pair(a.id, static_cast<int>(dem::mesh_wall_key(m, slot)));
        auto it = walls_.find(key);
        if (it == walls_.end()) {
          ++wall_collisions_;
          it = walls_.emplace(key, dem::ContactState{}).first;
        }
        it->second.seen = steps_;
        it->second.normal = n;
        const V3 vrel = a.v + a.w.cross(-dist * n);
        dem::ContactLaw law = s_.law;
        law.mu = s_.meshes[m].friction();
        const dem::ContactForce c = dem::contact_force(n, a.r - dist, dist, 0.0, vrel, 2 * a.r, it->second, law, h);
        a.F += c.force;
        a.T += c.torque1;
        wall_impulse_.add(6 + m, V3(-h * c.force));
      }
    }
  if (!s_.meshes.empty())  // histories of mesh contacts not renewed this step are dropped
    for (auto it = walls_.begin(); it != walls_.end();)
      it = (it->first.second >= 6 && it->second.seen != steps_) ? walls_.erase(it) : std::next(it);
}

// Crushing, the integration (seed 000 eqs 2.3-2.10), the periodic wrap and
// the outlets.
void DemReference::move(double h, const std::vector<std::size_t>& crushed) {
  // Grain crushing on compressive bond failure: radius and mass reduced.
  for (std::size_t i : crushed) {
    Particle& a = p_[i];
    a.r *= 1.0 - s_.crush;
    a.m *= std::pow(1.0 - s_.crush, 3);
    a.I = 0.4 * a.m * a.r * a.r;
  }
  for (auto& a : p_) {
    if (s_.fixed[a.species]) continue;  // held in place
    const V3 force = a.F + a.Fh + a.m * s_.gravity;
    dem::integrate(a.x, a.v, a.w, force, a.T + a.Th, a.m, a.I, s_.alpha, h);
  }
  // Periodic wrap; outlets remove particles whose centre left the box.
  std::vector<Particle> kept;
  for (auto& a : p_) {
    bool out = false;
    for (int k = 0; k < 3; ++k) {
      const double L = s_.upper[k] - s_.lower[k];
      if (s_.periodic[k]) a.x[k] -= L * std::floor((a.x[k] - s_.lower[k]) / L);
      if ((a.x[k] < s_.lower[k] && s_.faces[2 * k] == dem::Face::outlet) ||
          (a.x[k] > s_.upper[k] && s_.faces[2 * k + 1] == dem::Face::outlet))
        out = true;
    }
    if (out) {  // its contacts and bonds leave with it (a bond so gone is no failure)
      std::erase_if(contacts_,
                    [&](const auto& c) { return c.first.first == a.id || c.first.second == a.id; });
      std::erase_if(walls_, [&](const auto& c) { return c.first.first == a.id; });
    } else {
      kept.push_back(a);
    }
  }
  p_.swap(kept);
}

void DemReference::step(double h) {
  for (auto& p : p_) p.F = p.T = V3::Zero();
  std::vector<std::size_t> crushed;
  pair_forces(h, crushed);
  wall_forces(h);
  mesh_forces(h);
  move(h, crushed);
  time_ += h;
  ++steps_;
}

void DemReference::advance(double dt, long substeps) {
  const double h = dt / substeps;
  for (long n = 0; n < substeps; ++n) {
    // Crushed grains are lighter: split the step as the automatic step of the
    // lightest grain now requires (as dem does).
    long parts = 1;
    if (s_.crush > 0.0 && !p_.empty()) {
      double lightest = std::numeric_limits<double>::infinity();
      for (const auto& p : p_) lightest = std::min(lightest, p.m);
      if (s_.auto_step)
        parts = dem::split_for(h, dem::automatic_step(lightest, s_.law, s_.t_frac));
      else
        dem::check_fixed_step(h, lightest, s_.law);
    }
    for (long m = 0; m < parts; ++m) step(h / parts);
  }
}

const ParticleArrays& DemReference::particles() const {
  ParticleArrays& a = view_;
  a = ParticleArrays{};
  for (const auto& p : p_) {
    a.id.push_back(p.id);
    a.species.push_back(p.species);
    for (int k = 0; k < 3; ++k) {
      a.x.push_back(p.x[k]);
      a.v.push_back(p.v[k]);
      a.w.push_back(p.w[k]);
      a.force.push_back(p.F[k]);
    }
    a.radius.push_back(p.r);
    a.mass.push_back(p.m);
    a.inertia.push_back(p.I);
  }
  return a;
}

void DemReference::save(const std::string& dir) {
  std::vector<dem::SavedContact> list;
  for (const auto& [k, c] : contacts_) list.push_back(dem::SavedContact::from(k.first, k.second, c));
  for (const auto& [k, c] : walls_) list.push_back(dem::SavedContact::from(k.first, -1 - k.second, c));
  std::sort(list.begin(), list.end(), [](const auto& x, const auto& y) { return std::tie(x.a, x.b) < std::tie(y.a, y.b); });
  dem::save_state(comm_, dir, time_, steps_, particles(), list, {collisions_, wall_collisions_, broken_});
}

void DemReference::load(const std::string& dir, long steps, double time) {
  ParticleArrays a;
  std::vector<dem::SavedContact> list;
  dem::EventCounts counts;
  dem::load_state(dir, params_, a, list, &counts);
  collisions_ = counts.collisions;
  wall_collisions_ = counts.wall_collisions;
  broken_ = counts.broken_bonds;
  p_.clear();
  for (std::size_t i = 0; i < a.size(); ++i)
    p_.push_back({a.id[i], a.species[i], V3(&a.x[3 * i]), V3(&a.v[3 * i]), V3(&a.w[3 * i]), a.radius[i], a.mass[i],
                  a.inertia[i], V3::Zero(), V3::Zero(), V3::Zero(), V3::Zero()});
  // In id order, as a straight run keeps them (dem on N ranks writes its
  // ranks' particles one rank after another): the pairs' order and their
  // (smaller id, larger id) history keys depend on it.
  std::sort(p_.begin(), p_.end(), [](const Particle& x, const Particle& y) { return x.id < y.id; });
  contacts_.clear();
  walls_.clear();
  for (const auto& c : list) {
    if (!c.wall())
      contacts_[{c.a, c.b}] = c.state();
    else
      walls_[{c.a, static_cast<int>(c.wall_face())}] = c.state();
  }
  // The steps and the clock as the checkpoint kept them: crushing grains
  // take extra sub-steps, and the clock is the sum of the steps taken (the
  // windows' count alone would differ; the times of events and snapshots
  // then by round-off). A checkpoint without them: the driver's.
  const long saved = coflow::output::read_step(dir + "/particles.h5");
  steps_ = saved >= 0 ? saved : steps;
  time_ = saved >= 0 ? coflow::output::read_time(dir + "/particles.h5") : time;
}

void DemReference::set_hydrodynamic(std::span<const double> force, std::span<const double> torque) {
  for (std::size_t i = 0; i < p_.size(); ++i) {
    p_[i].Fh = V3(&force[3 * i]);
    p_[i].Th = V3(&torque[3 * i]);
  }
}

ParticleStats DemReference::stats() {
  ParticleStats st;
  st.count = static_cast<long>(p_.size());
  for (const auto& p : p_) {
    for (int k = 0; k < 3; ++k) st.momentum[k] += p.m * p.v[k];
    st.kinetic_energy += 0.5 * p.m * p.v.squaredNorm();
    st.rotational_energy += 0.5 * p.I * p.w.squaredNorm();
  }
  st.collisions = collisions_;
  st.wall_collisions = wall_collisions_;
  st.broken_bonds = broken_;
  collisions_ = wall_collisions_ = 0;  // broken_bonds is cumulative
  return st;
}

}  // namespace coflow::particles
