#include "particles/event_log.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "coflow/gather.hpp"
#include "coflow/output.hpp"

namespace coflow::particles {

EventLog::EventLog(coupler::Session& s, const config::OutputParams& out, bool point_particles, long w0)
    : s_(s),
      collisions_(out.collision_events),
      bonds_(out.bond_events),
      impacts_(out.collision_events && point_particles) {
  if (s.rank() != 0) return;
  // A restart appends to the files of the run it goes on from; a file that
  // is not there (a restart into a new directory, or events asked for
  // only now) starts with its header.
  const auto open = [&](std::ofstream& f, const char* name, const char* header) {
    const std::string dir = s.output_dir() + "/events", path = dir + "/" + name;
    std::filesystem::create_directories(dir);
    std::error_code ec;
    const bool fresh = w0 == 0 || !std::filesystem::exists(path) || std::filesystem::file_size(path, ec) == 0;
    f.open(path, fresh ? std::ios::trunc : std::ios::app);
    if (fresh) f << header;
  };
  if (collisions_) open(collisions_csv_, "collisions.csv", "time,i,j,angle,relative_speed,normal_speed\n");
  if (impacts_) open(impacts_csv_, "impacts.csv", "time,id,wall,x,y,z,angle,speed\n");
  if (bonds_) open(bonds_csv_, "bonds.csv", "time,i,j,mode,normal_force,shear_force\n");
}

void EventLog::save(const std::string& dir) const {
  if (s_.rank() != 0 || !wanted()) return;
  std::string text;
  for (const char* name : {"collisions.csv", "bonds.csv", "impacts.csv"}) {
    const std::string path = s_.output_dir() + "/events/" + name;
    std::error_code ec;
    if (const auto bytes = std::filesystem::file_size(path, ec); !ec)
      text += fmt::format("{} {}\n", name, bytes);
  }
  output::atomic_write(dir + "/events.txt", text);
}

void EventLog::write(const ParticleEvents& ev) {
  if (!wanted()) return;
  write_pairs(ev);  // the order of the two gathers is every rank's
  write_impacts(ev);
  if (s_.rank() != 0) return;
  collisions_csv_.flush();
  bonds_csv_.flush();
  impacts_csv_.flush();
  // An event file that could not be opened or written (a full disk, no
  // permission): the run stops rather than finish with a short log.
  for (const auto* f : {&collisions_csv_, &bonds_csv_, &impacts_csv_})
    if (f->is_open() && !*f)
      throw std::runtime_error("cannot write the event logs in " + s_.output_dir() + "/events");
  if ((collisions_ && !collisions_csv_.is_open()) || (bonds_ && !bonds_csv_.is_open()) ||
      (impacts_ && !impacts_csv_.is_open()))
    throw std::runtime_error("cannot open the event logs in " + s_.output_dir() + "/events");
}

// Collisions and bond failures: (kind, time, i, j, four values) rows.
void EventLog::write_pairs(const ParticleEvents& ev) {
  std::vector<double> local;
  for (const auto& e : ev.collisions)
    local.insert(local.end(), {0.0, e.time, double(e.i), double(e.j), e.angle, e.relative_speed, e.normal_speed});
  for (const auto& e : ev.bonds)
    local.insert(local.end(), {1.0, e.time, double(e.i), double(e.j), double(static_cast<int>(e.mode)),
                               e.normal_force, e.shear_force});
  const std::vector<double> all = coupler::gather_to_root<double>(s_.comm(), local, MPI_DOUBLE);
  if (s_.rank() != 0) return;
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
      collisions_csv_ << fmt::format("{:.17g},{},{},{:.17g},{:.17g},{:.17g}\n", e[1], std::int64_t(e[2]),
                                     std::int64_t(e[3]), e[4], e[5], e[6]);
    else
      bonds_csv_ << fmt::format("{:.17g},{},{},{},{:.17g},{:.17g}\n", e[1], std::int64_t(e[2]), std::int64_t(e[3]),
                                modes[static_cast<int>(e[4])], e[5], e[6]);
  }
}

// Wall impacts (point particles): time, id, wall, contact point, angle, speed.
void EventLog::write_impacts(const ParticleEvents& ev) {
  std::vector<double> hits;
  for (const auto& e : ev.impacts)
    hits.insert(hits.end(), {e.time, double(e.id), double(e.wall), e.point[0], e.point[1], e.point[2], e.angle, e.speed});
  const std::vector<double> all = coupler::gather_to_root<double>(s_.comm(), hits, MPI_DOUBLE);
  if (s_.rank() != 0 || !impacts_csv_.is_open()) return;
  constexpr std::size_t H = 8;
  std::vector<std::size_t> by(all.size() / H);
  for (std::size_t n = 0; n < by.size(); ++n) by[n] = n;
  std::sort(by.begin(), by.end(), [&](std::size_t a, std::size_t b) {
    return std::lexicographical_compare(&all[H * a], &all[H * a + 3], &all[H * b], &all[H * b + 3]);
  });
  for (std::size_t n : by) {
    const double* e = &all[H * n];
    impacts_csv_ << fmt::format("{:.17g},{},{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", e[0], std::int64_t(e[1]),
                                std::int64_t(e[2]), e[3], e[4], e[5], e[6], e[7]);
  }
}

}  // namespace coflow::particles
