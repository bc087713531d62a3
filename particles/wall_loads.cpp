#include "particles/wall_loads.hpp"

#include <fmt/format.h>

namespace coflow::particles {

std::unique_ptr<coupler::ImpulseSeries> make_wall_loads(coupler::Session& s, const ParticleParams& params, long w0) {
  const auto& d = s.config().domain;
  const char* faces[] = {"x-", "x+", "y-", "y+", "z-", "z+"};
  std::vector<std::string> names;
  std::vector<std::size_t> slots;
  for (int f = 0; f < 6; ++f)
    if (!d.periodic[f / 2] && params.boundaries[f] != "outlet") {
      names.push_back(faces[f]);
      slots.push_back(static_cast<std::size_t>(f));
    }
  std::size_t meshes = 0;
  for (const auto& w : params.walls)
    if (!w.mesh.empty()) {
      names.push_back(fmt::format("mesh{}", meshes));
      slots.push_back(6 + meshes++);
    }
  return std::make_unique<coupler::ImpulseSeries>(s, "walls", std::move(names), std::move(slots), 6 + meshes, w0);
}

}  // namespace coflow::particles
