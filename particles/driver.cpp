#include "particles/driver.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <unordered_map>

#include <fmt/format.h>

#include "coflow/log.hpp"
#include "coflow/output.hpp"
#include "coflow/exchange.hpp"
#include "coflow/finite.hpp"
#include "coflow/gather.hpp"
#include "coflow/protocol.hpp"
#include "particles/schema.hpp"

namespace coflow::particles {


void run(coupler::Session& s) {
  const auto& cfg = s.config();
  const auto& info = cfg.component("particles");
  if (info.variant == "external")
    throw std::runtime_error(
        "particles.solver is 'external': run your own executable with `coflow run --exe particles=PATH`");
  ParticleParams params;
  {
    config::Reader r(cfg.resolved["particles"], cfg.file, "particles");
    params.visit(r, cfg);
    r.check();
  }
  const auto& entry = registry().at(info.variant);
  ParticleSolver::Setup setup{cfg, params, s.decomposition(), s.rank(), s.comm()};
  config::Reader r(YAML::Node(), cfg.file, "particles");
  std::unique_ptr<ParticleSolver> solver = entry.create(setup, r);

  // Particles sub-cycle inside the fluid's window; alone, one window per output
  // interval.
  s.negotiate_window(0.0);
  const long substeps = s.substeps(solver->time_step());
  log::info("particles: step {:.4g} s, {} sub-steps of {:.4g} s per window", solver->time_step(), substeps,
            s.window() / substeps);

  const long w0 = s.restart_window();
  if (w0 > 0) solver->load(s.restart_dir(), w0 * substeps, w0 * s.window());

  output::Series series;
  if (s.rank() == 0)
    series = output::Series(s.output_dir() + "/series/particles.csv",
                            {"time", "count", "momentum_x", "momentum_y", "momentum_z", "kinetic_energy",
                             "collisions", "wall_collisions", "broken_bonds", "rotational_energy"},
                            w0 > 0);
  // Event logs: each rank's events of the window, gathered on rank 0 and written
  // in (time, i, j) order, so the file does not depend on the rank count.
  const auto& out = cfg.run.output;
  solver->record_events(out.collision_events, out.bond_events);
  std::ofstream collisions_csv, bonds_csv, impacts_csv;
  if (s.rank() == 0) {
    const auto mode = w0 > 0 ? std::ios::app : std::ios::trunc;
    if (out.collision_events) {
      std::filesystem::create_directories(s.output_dir() + "/events");
      collisions_csv.open(s.output_dir() + "/events/collisions.csv", mode);
      if (w0 == 0) collisions_csv << "time,i,j,angle,relative_speed,normal_speed\n";
      if (params.point_particles) {
        impacts_csv.open(s.output_dir() + "/events/impacts.csv", mode);
        if (w0 == 0) impacts_csv << "time,id,wall,x,y,z,angle,speed\n";
      }
    }
    if (out.bond_events) {
      std::filesystem::create_directories(s.output_dir() + "/events");
      bonds_csv.open(s.output_dir() + "/events/bonds.csv", mode);
      if (w0 == 0) bonds_csv << "time,i,j,mode,normal_force,shear_force\n";
    }
  }
  auto write_events = [&] {
    if (!out.collision_events && !out.bond_events) return;
    const ParticleEvents ev = solver->take_events();
    std::vector<double> local;
    for (const auto& e : ev.collisions)
      local.insert(local.end(), {0.0, e.time, double(e.i), double(e.j), e.angle, e.relative_speed, e.normal_speed});
    for (const auto& e : ev.bonds)
      local.insert(local.end(), {1.0, e.time, double(e.i), double(e.j), double(static_cast<int>(e.mode)),
                                 e.normal_force, e.shear_force});
    const std::vector<double> all = coupler::gather_to_root<double>(s.comm(), local, MPI_DOUBLE);
    // Wall impacts (point particles): time, id, wall, contact point, angle, speed.
    std::vector<double> hits;
    for (const auto& e : ev.impacts)
      hits.insert(hits.end(), {e.time, double(e.id), double(e.wall), e.point[0], e.point[1], e.point[2], e.angle, e.speed});
    const std::vector<double> all_hits = coupler::gather_to_root<double>(s.comm(), hits, MPI_DOUBLE);
    if (s.rank() == 0 && impacts_csv.is_open()) {
      constexpr std::size_t H = 8;
      std::vector<std::size_t> by(all_hits.size() / H);
      for (std::size_t n = 0; n < by.size(); ++n) by[n] = n;
      std::sort(by.begin(), by.end(), [&](std::size_t a, std::size_t b) {
        return std::lexicographical_compare(&all_hits[H * a], &all_hits[H * a + 3], &all_hits[H * b], &all_hits[H * b + 3]);
      });
      for (std::size_t n : by) {
        const double* e = &all_hits[H * n];
        impacts_csv << fmt::format("{:.17g},{},{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", e[0], std::int64_t(e[1]),
                                   std::int64_t(e[2]), e[3], e[4], e[5], e[6], e[7]);
      }
      impacts_csv.flush();
    }
    if (s.rank() != 0) return;
    constexpr std::size_t W = 7;
    std::vector<std::size_t> order(all.size() / W);
    for (std::size_t n = 0; n < order.size(); ++n) order[n] = n;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return std::lexicographical_compare(&all[W * a], &all[W * a + 4], &all[W * b], &all[W * b + 4]);
    });
    static constexpr const char* modes[] = {"", "tension", "compression", "shear"};
    for (std::size_t n : order) {
      const double* e = &all[W * n];
      if (e[0] == 0.0)
        collisions_csv << fmt::format("{:.17g},{},{},{:.17g},{:.17g},{:.17g}\n", e[1], std::int64_t(e[2]),
                                      std::int64_t(e[3]), e[4], e[5], e[6]);
      else
        bonds_csv << fmt::format("{:.17g},{},{},{},{:.17g},{:.17g}\n", e[1], std::int64_t(e[2]), std::int64_t(e[3]),
                                 modes[static_cast<int>(e[4])], e[5], e[6]);
    }
    collisions_csv.flush();
    bonds_csv.flush();
  };
  auto write_output = [&](long w) {
    coupler::Timer t(coupler::trace().io_s);
    if (s.series_due(w)) {
      const ParticleStats st = solver->stats();
      const double row[] = {solver->time(), double(st.count), st.momentum[0], st.momentum[1], st.momentum[2],
                            st.kinetic_energy, double(st.collisions), double(st.wall_collisions),
                            double(st.broken_bonds), st.rotational_energy};
      if (s.rank() == 0) series.row(row);
      s.set_final("particles.count", double(st.count));
      s.set_final("particles.kinetic_energy", st.kinetic_energy);
      s.set_final("particles.broken_bonds", double(st.broken_bonds));
    }
    if (s.snapshot_due(w)) {
      const ParticleArrays& p = solver->particles();
      std::vector<double> diam(p.radius);
      const std::vector<output::PointField> fields{{"position", 3, p.x},       {"velocity", 3, p.v},
                                                   {"angular_velocity", 3, p.w}, {"radius", 1, p.radius},
                                                   {"force", 3, p.force}};
      output::write_points(s.comm(), fmt::format("{}/{}", s.component_dir(), output::snapshot_name(w)),
                           solver->time(), w, p.size(), p.id, p.species, fields);
      long count = static_cast<long>(p.size()), total = 0;
      MPI_Allreduce(&count, &total, 1, MPI_LONG, MPI_SUM, s.comm());
      s.snapshot_written(w, solver->time(), static_cast<std::size_t>(total),
                         {"position", "velocity", "angular_velocity", "radius", "force"});
    }
  };
  // Coupled to the immersed component: each window the particle states go out
  // (routed to the immersed ranks whose grid block, or ghost layer, they cover)
  // and the hydrodynamic force and torque on each come back, held constant over
  // the window's sub-steps.
  // With immersed method point, the fluid at each particle comes back instead
  // (one copy per particle), and after the sub-steps each particle's impulse of
  // the fluid forces goes out for the momentum source.
  std::unique_ptr<coupler::PointExchange> to_immersed, impulse_out;
  const bool point = s.has_partner("immersed") && cfg.component("immersed").variant == "point";
  if (s.has_partner("immersed")) {
    const auto dest = s.decomposition_of("immersed", s.partner_ranks("immersed"));
    const auto h = cfg.domain.spacing();
    to_immersed = std::make_unique<coupler::PointExchange>(
        s.partner("immersed"), coupler::PointExchange::Role::origin, dest, cfg.domain.lower, h,
        sizeof(protocol::ParticleRecord), point ? sizeof(protocol::FluidAtParticle) : sizeof(protocol::ParticleLoad),
        protocol::kTagParticles, point ? 0 : coupling_ghost_cells(params, cfg));
    if (point)
      impulse_out = std::make_unique<coupler::PointExchange>(
          s.partner("immersed"), coupler::PointExchange::Role::origin, dest, cfg.domain.lower, h,
          sizeof(protocol::ParticleImpulse), sizeof(double), protocol::kTagImpulse, 0);
  }
  std::vector<std::byte> records, loads;
  std::vector<std::array<double, 3>> positions;
  std::vector<double> hforce, htorque;
  std::vector<std::int64_t> sent_ids;
  // serial-explicit: the loads of this window's states, before the sub-steps.
  // parallel-explicit: the particles sub-cycle on the previous window's loads
  // while the immersed side and the fluid compute this window's; those arrive
  // after the sub-steps, are matched to the particles by id (a particle may
  // have moved to another rank meanwhile) and act in the next window.
  const bool lagged = to_immersed && !point && cfg.coupling.scheme == config::Scheme::parallel_explicit;
  auto send_states = [&] {
    const ParticleArrays& p = solver->particles();
    const std::size_t n = p.size();
    records.resize(n * sizeof(protocol::ParticleRecord));
    positions.resize(n);
    sent_ids.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      protocol::ParticleRecord rec{};
      rec.id = p.id[i];
      for (int d = 0; d < 3; ++d) {
        rec.x[d] = p.x[3 * i + d];
        rec.v[d] = p.v[3 * i + d];
        rec.w[d] = p.w[3 * i + d];
        positions[i][d] = rec.x[d];
      }
      rec.radius = p.radius[i];
      rec.mass = p.mass[i];
      sent_ids[i] = p.id[i];
      std::memcpy(records.data() + i * sizeof rec, &rec, sizeof rec);
    }
    to_immersed->send(records, positions);
  };
  // Loads as (id, force, torque) rows of 7 doubles.
  auto receive_loads = [&] {
    const std::size_t n = sent_ids.size();
    loads.assign(n * sizeof(protocol::ParticleLoad), std::byte{0});
    to_immersed->receive_results(loads, protocol::add_load);
    std::vector<double> rows(7 * n);
    for (std::size_t i = 0; i < n; ++i) {
      protocol::ParticleLoad l;
      std::memcpy(&l, loads.data() + i * sizeof l, sizeof l);
      rows[7 * i] = static_cast<double>(sent_ids[i]);
      for (int d = 0; d < 3; ++d) {
        rows[7 * i + 1 + d] = l.force[d];
        rows[7 * i + 4 + d] = l.torque[d];
      }
    }
    return rows;
  };
  // Hand the rows to the particles that hold these ids now; rows whose particle
  // is on another rank travel to all ranks (few: those that crossed a border in
  // the window); a particle that left the domain drops its row.
  auto apply_loads = [&](const std::vector<double>& rows) {
    const ParticleArrays& p = solver->particles();
    const std::size_t n = p.size();
    std::unordered_map<std::int64_t, std::size_t> slot;
    slot.reserve(n);
    for (std::size_t i = 0; i < n; ++i) slot.emplace(p.id[i], i);
    hforce.assign(3 * n, 0.0);
    htorque.assign(3 * n, 0.0);
    std::vector<double> away;
    auto put = [&](const double* row) {
      const auto it = slot.find(static_cast<std::int64_t>(row[0]));
      if (it == slot.end()) return false;
      for (int d = 0; d < 3; ++d) {
        hforce[3 * it->second + d] = row[1 + d];
        htorque[3 * it->second + d] = row[4 + d];
      }
      return true;
    };
    for (std::size_t k = 0; k < rows.size(); k += 7)
      if (!put(&rows[k])) away.insert(away.end(), &rows[k], &rows[k] + 7);
    if (s.size() > 1) {
      const std::vector<double> all = coupler::allgather<double>(s.comm(), away, MPI_DOUBLE);
      for (std::size_t k = 0; k < all.size(); k += 7) put(&all[k]);
    }
    solver->set_hydrodynamic(hforce, htorque);
  };
  // The loads waiting for the next window belong to a checkpoint (lagged only).
  std::vector<double> pending;
  auto save_pending = [&](const std::string& dir) {
    const std::vector<double> all = coupler::gather_to_root<double>(s.comm(), pending, MPI_DOUBLE);
    if (s.rank() != 0) return;
    std::ofstream f(dir + "/hydrodynamic.csv");
    f << "id,fx,fy,fz,tx,ty,tz\n";
    for (std::size_t k = 0; k < all.size(); k += 7)
      f << fmt::format("{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", std::int64_t(all[k]), all[k + 1],
                       all[k + 2], all[k + 3], all[k + 4], all[k + 5], all[k + 6]);
  };
  auto load_pending = [&](const std::string& dir) {
    std::ifstream f(dir + "/hydrodynamic.csv");
    if (!f) throw std::runtime_error(dir + "/hydrodynamic.csv: missing (the checkpoint of a parallel-explicit run)");
    std::string line;
    std::getline(f, line);
    std::vector<double> rows;
    while (std::getline(f, line)) {
      std::istringstream in(line);
      std::string cell;
      while (std::getline(in, cell, ',')) rows.push_back(std::stod(cell));
    }
    if (rows.size() % 7 != 0) throw std::runtime_error(dir + "/hydrodynamic.csv: malformed");
    // Every rank read all rows: keep those of its own particles.
    const ParticleArrays& p = solver->particles();
    std::unordered_map<std::int64_t, std::size_t> slot;
    for (std::size_t i = 0; i < p.size(); ++i) slot.emplace(p.id[i], i);
    std::vector<double> mine;
    for (std::size_t k = 0; k < rows.size(); k += 7)
      if (slot.count(static_cast<std::int64_t>(rows[k]))) mine.insert(mine.end(), &rows[k], &rows[k] + 7);
    pending = mine;
    apply_loads(mine);
  };
  if (lagged && w0 > 0) load_pending(s.restart_dir());
  std::vector<double> samples, impulse;
  std::vector<std::byte> fluid_bytes, impulse_records;
  auto receive_fluid = [&] {
    const std::size_t n = sent_ids.size();
    fluid_bytes.assign(n * sizeof(protocol::FluidAtParticle), std::byte{0});
    to_immersed->receive_results(fluid_bytes);
    samples.resize(ParticleSolver::kFluidValues * n);
    for (std::size_t i = 0; i < n; ++i) {
      protocol::FluidAtParticle f;
      std::memcpy(&f, fluid_bytes.data() + i * sizeof f, sizeof f);
      double* row = &samples[ParticleSolver::kFluidValues * i];
      for (int d = 0; d < 3; ++d) {
        row[d] = f.u[d];
        row[3 + d] = f.vorticity[d];
      }
      row[6] = f.k;
      row[7] = f.epsilon;
      row[8] = f.rho;
      row[9] = f.mu;
    }
    solver->set_fluid(samples);
  };
  auto send_impulses = [&] {
    solver->take_impulse(impulse);
    const ParticleArrays& p = solver->particles();
    const std::size_t n = p.size();
    impulse_records.resize(n * sizeof(protocol::ParticleImpulse));
    positions.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      protocol::ParticleImpulse rec{};
      rec.id = p.id[i];
      for (int d = 0; d < 3; ++d) {
        rec.x[d] = p.x[3 * i + d];
        rec.impulse[d] = impulse[3 * i + d];
        positions[i][d] = rec.x[d];
      }
      std::memcpy(impulse_records.data() + i * sizeof rec, &rec, sizeof rec);
    }
    impulse_out->send(impulse_records, positions);
  };

  // Every window, before the state goes anywhere: a particle whose state is
  // not finite stops the run here, named, rather than in the fluid later.
  const bool point_variant = params.point_particles;
  auto check_state = [&] {
    const ParticleArrays& p = solver->particles();
    const std::string hint = point_variant
                                 ? "the step may be too long for the particles' response time: set particles.time_step: auto"
                                 : "the step may be too large for the contact stiffness (seed 000 eq. 2.19): lower "
                                   "particles.time_step_fraction or the stiffness";
    coupler::check_finite(s.comm(), {fmt::format("particles ({})", info.variant), "particle", hint}, solver->steps(),
                          solver->time(), {{"position", p.x}, {"velocity", p.v}, {"angular velocity", p.w},
                                           {"force", p.force}}, 3, p.id);
  };
  if (w0 == 0) write_output(0);
  for (long w = w0 + 1; w <= s.windows(); ++w) {
    if (to_immersed) send_states();
    if (point) receive_fluid();
    if (to_immersed && !lagged && !point) apply_loads(receive_loads());
    solver->advance(s.window(), substeps);
    if (point) send_impulses();
    if (lagged) {
      pending = receive_loads();
      apply_loads(pending);
    }
    check_state();
    coupler::trace().steps = solver->steps();
    write_events();
    write_output(w);
    s.checkpoint(w, [&](const std::string& dir) {
      solver->save(dir);
      if (lagged) save_pending(dir);
    });
    s.window_done(w);
  }
}

}  // namespace coflow::particles
