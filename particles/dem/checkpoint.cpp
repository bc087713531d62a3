#include "particles/dem/checkpoint.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <stdexcept>
#include <tuple>

#include "coflow/output.hpp"

namespace coflow::particles::dem {

void save_state(MPI_Comm comm, const std::string& dir, double time, long steps, const ParticleArrays& p,
                const std::vector<SavedContact>& contacts, const EventCounts& counts) {
  output::write_points(comm, dir + "/particles.h5", time, steps, p.size(), p.id, p.species,
                       {{"position", 3, p.x}, {"velocity", 3, p.v}, {"angular_velocity", 3, p.w},
                        {"radius", 1, p.radius}, {"force", 3, p.force}, {"mass", 1, p.mass},
                        {"inertia", 1, p.inertia}});
  std::vector<std::int64_t> a;
  std::vector<std::int32_t> bonded;
  std::vector<double> partner, shear, normal;
  for (const auto& c : contacts) {
    a.push_back(c.a);
    bonded.push_back(c.bonded ? 1 : 0);
    partner.push_back(static_cast<double>(c.b));
    shear.insert(shear.end(), c.shear.begin(), c.shear.end());
    normal.insert(normal.end(), c.normal.begin(), c.normal.end());
  }
  output::write_points(comm, dir + "/contacts.h5", time, steps, contacts.size(), a, bonded,
                       {{"partner", 1, partner}, {"shear", 3, shear}, {"normal", 3, normal}});
  const long mine[3] = {counts.collisions, counts.wall_collisions, counts.broken_bonds};
  long total[3] = {0, 0, 0};
  MPI_Allreduce(mine, total, 3, MPI_LONG, MPI_SUM, comm);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  const double value[3] = {static_cast<double>(total[0]), static_cast<double>(total[1]),
                           static_cast<double>(total[2])};
  const std::size_t rows = rank == 0 ? 1 : 0;
  output::write_tables(comm, dir + "/counters.h5", time, steps,
                       {{"collisions", 1, rows, false, {&value[0], rows}, {}},
                        {"wall_collisions", 1, rows, false, {&value[1], rows}, {}},
                        {"broken_bonds", 1, rows, false, {&value[2], rows}, {}}});
}

namespace {

// A damaged checkpoint (a value that is not finite; a radius or a mass that is
// not positive) is refused, naming the file and the particle (`per` values
// each). Every rank reads the whole file, so every rank throws alike.
void refuse_damaged(const std::string& file, const std::vector<double>& id, const char* name,
                    const std::vector<double>& v, std::size_t per, bool positive) {
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]) || (positive && !(v[i] > 0.0)))
      throw std::runtime_error(fmt::format(
          "{}: particle {} has a {} that is {} ({}): the checkpoint is damaged; restart from another one",
          file, i / per < id.size() ? static_cast<long long>(id[i / per]) : -1LL, name,
          std::isfinite(v[i]) ? "not positive" : "not finite", v[i]));
}

// Identifiers read as doubles (ids, species indices, partners): whole
// numbers, at least `least` and below 2^62 in size, before they are cast to
// integers (a cast of a NaN or of one out of range is undefined).
void refuse_not_whole(const std::string& file, const char* name, const std::vector<double>& v, double least) {
  for (double x : v)
    if (!(std::isfinite(x) && x == std::floor(x) && x >= least && std::abs(x) < 0x1p62))
      throw std::runtime_error(fmt::format(
          "{}: the {} {} is not a valid whole number: the checkpoint is damaged; restart from another one",
          file, name, x));
}

// A dataset must hold `per` values for each of the `count` entries (a
// truncated or foreign one would be read past its end).
void refuse_length(const std::string& file, const char* name, const std::vector<double>& v, std::size_t per,
                   std::size_t count) {
  if (v.size() != per * count)
    throw std::runtime_error(
        fmt::format("{}: the {} dataset holds {} values for {} entries of {}: the checkpoint is "
                    "damaged; restart from another one",
                    file, name, v.size(), count, per));
}

// A count a checkpoint saved; 0 from one written before it was kept.
long read_count(const std::string& file, const char* name) {
  if (!std::filesystem::exists(file) || !output::has_dataset(file, name)) return 0;
  const auto v = output::read_dataset(file, name);
  refuse_not_whole(file, name, v, 0.0);
  return v.empty() ? 0 : static_cast<long>(v[0]);
}

}  // namespace

void load_state(const std::string& dir, const ParticleParams& params, ParticleArrays& p,
                std::vector<SavedContact>& contacts, EventCounts* counts) {
  const std::string pf = dir + "/particles.h5", cf = dir + "/contacts.h5";
  const auto id = output::read_dataset(pf, "id");
  const auto sp = output::read_dataset(pf, "species");
  p = ParticleArrays{};
  p.x = output::read_dataset(pf, "position");
  p.v = output::read_dataset(pf, "velocity");
  p.w = output::read_dataset(pf, "angular_velocity");
  p.radius = output::read_dataset(pf, "radius");
  p.force = output::read_dataset(pf, "force");
  // Stored, not recomputed: a restart must continue bit for bit.
  p.mass = output::read_dataset(pf, "mass");
  p.inertia = output::read_dataset(pf, "inertia");
  for (const auto& [name, v, per, positive] :
       {std::tuple{"position", &p.x, 3, false}, std::tuple{"velocity", &p.v, 3, false},
        std::tuple{"angular velocity", &p.w, 3, false}, std::tuple{"radius", &p.radius, 1, true},
        std::tuple{"force", &p.force, 3, false}, std::tuple{"mass", &p.mass, 1, true},
        std::tuple{"moment of inertia", &p.inertia, 1, false}}) {
    refuse_length(pf, name, *v, static_cast<std::size_t>(per), id.size());
    refuse_damaged(pf, id, name, *v, static_cast<std::size_t>(per), positive);
  }
  refuse_length(pf, "species", sp, 1, id.size());
  refuse_not_whole(pf, "particle id", id, -0x1p62);
  refuse_not_whole(pf, "species index", sp, 0.0);
  for (std::size_t i = 0; i < id.size(); ++i) {
    p.id.push_back(static_cast<std::int64_t>(id[i]));
    const auto s = static_cast<std::size_t>(sp[i]);
    if (s >= params.species.size()) throw std::runtime_error(pf + ": unknown species index in the checkpoint");
    p.species.push_back(static_cast<std::int32_t>(s));
  }
  const auto a = output::read_dataset(cf, "id");
  const auto bonded = output::read_dataset(cf, "species");
  const auto partner = output::read_dataset(cf, "partner");
  const auto shear = output::read_dataset(cf, "shear");
  // Checkpoints before the directions were kept have none (zero).
  const auto normal = output::has_dataset(cf, "normal") ? output::read_dataset(cf, "normal")
                                                        : std::vector<double>(shear.size(), 0.0);
  for (const auto& [name, v, per] :
       {std::tuple{"species (bonded)", &bonded, 1}, std::tuple{"partner", &partner, 1},
        std::tuple{"shear", &shear, 3}, std::tuple{"normal", &normal, 3}})
    refuse_length(cf, name, *v, static_cast<std::size_t>(per), a.size());
  refuse_damaged(cf, a, "contact history (tangential spring)", shear, 3, false);
  refuse_damaged(cf, a, "contact history (direction)", normal, 3, false);
  refuse_not_whole(cf, "particle id", a, -0x1p62);
  refuse_not_whole(cf, "partner (a particle id, or -1 - a wall's index)", partner, -0x1p62);
  contacts.clear();
  for (std::size_t k = 0; k < a.size(); ++k)
    contacts.push_back({static_cast<std::int64_t>(a[k]),
                        static_cast<std::int64_t>(partner[k]),
                        {shear[3 * k], shear[3 * k + 1], shear[3 * k + 2]},
                        bonded[k] != 0,
                        {normal[3 * k], normal[3 * k + 1], normal[3 * k + 2]}});
  if (counts) {
    const std::string file = dir + "/counters.h5";
    *counts = {read_count(file, "collisions"), read_count(file, "wall_collisions"),
               read_count(file, "broken_bonds")};
  }
}

}  // namespace coflow::particles::dem
