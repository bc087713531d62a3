#include "particles/store/particle_store.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>

#include <fmt/format.h>

namespace coflow::particles::store {

ParticleStore::ParticleStore(ParticleArrays& a) : arrays_(a) {
  add("id", 1, always, a.id);
  add("species", 1, always, a.species);
  add("position", 3, always, a.x);
  add("velocity", 3, always, a.v);
  add("angular_velocity", 3, always, a.w);
  add("radius", 1, always, a.radius);
  add("mass", 1, always, a.mass);
  add("inertia", 1, always, a.inertia);
  add("force", 3, migrates, a.force);
}

std::size_t ParticleStore::row_doubles(Travel with) const {
  std::size_t n = 0;
  for (const auto& c : columns_)
    if (c->travels(with)) n += c->doubles();
  return n;
}

void ParticleStore::pack(std::size_t i, Travel with, std::vector<double>& out) const {
  std::size_t at = out.size();
  out.resize(at + row_doubles(with));
  for (const auto& c : columns_) {
    if (!c->travels(with)) continue;
    c->pack(i, out.data() + at);
    at += c->doubles();
  }
}

void ParticleStore::unpack(const double* row, Travel with) {
  for (const auto& c : columns_) {
    if (!c->travels(with)) {
      c->append_default();
      continue;
    }
    c->unpack(row);
    row += c->doubles();
  }
}

std::size_t ParticleStore::append() {
  for (const auto& c : columns_) c->append_default();
  return size() - 1;
}

void ParticleStore::unpack_all(const std::vector<double>& rows, Travel with) {
  const std::size_t w = row_doubles(with);
  if (w == 0 || rows.size() % w != 0)
    throw std::logic_error(fmt::format("particle store: {} doubles are not whole rows of {}", rows.size(), w));
  for (std::size_t k = 0; k < rows.size(); k += w) unpack(&rows[k], with);
}

void ParticleStore::keep(const std::vector<char>& mask) {
  const std::vector<char> copy = mask;  // the mask may be a column itself (dem's owned)
  for (const auto& c : columns_) c->keep(copy);
}

void ParticleStore::sort_by_id() {
  std::vector<std::size_t> order(size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return arrays_.id[a] < arrays_.id[b]; });
  for (const auto& c : columns_) c->permute(order);
}

void ParticleStore::check_sizes() const {
  for (const auto& c : columns_)
    if (c->rows() != size())
      throw std::logic_error(fmt::format("particle store: attribute {} holds {} particles, id holds {}", c->name(),
                                         c->rows(), size()));
}

}  // namespace coflow::particles::store
