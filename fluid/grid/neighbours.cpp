#include "fluid/grid/neighbours.hpp"

#include <stdexcept>

#include <fmt/format.h>

namespace coflow::fluid::grid {

namespace {
// Cells beyond side d of block b, or false where none exist (a wall).
bool beyond(const coupler::Decomposition& dec, const coupler::Box& b, const int d[3], coupler::Index3& probe) {
  for (int a = 0; a < 3; ++a) {
    probe[a] = d[a] < 0 ? b.lo[a] - 1 : d[a] > 0 ? b.hi[a] : b.lo[a];
    if ((probe[a] < 0 || probe[a] >= dec.cells()[a]) && !dec.periodic()[a]) return false;
  }
  return true;
}
}  // namespace

std::vector<Neighbour> neighbours(const coupler::Decomposition& dec, int rank, const coupler::Index3& ghost) {
  const coupler::Box& b = dec.block(rank);
  for (int a = 0; a < 3; ++a)
    for (int r = 0; r < dec.ranks(); ++r)
      if (ghost[a] > 0 && dec.block(r).extent(a) < ghost[a] && (dec.dims()[a] > 1 || dec.periodic()[a]))
        throw std::runtime_error(fmt::format("fluid grid: block {} has {} cells along axis {}, fewer than the {} ghost "
                                             "layers; use fewer ranks along that axis",
                                             r, dec.block(r).extent(a), a, ghost[a]));
  std::vector<Neighbour> out;
  const long g[3] = {ghost[0] > 0 ? 1 : 0, ghost[1] > 0 ? 1 : 0, ghost[2] > 0 ? 1 : 0};
  for (int dz = -int(g[2]); dz <= g[2]; ++dz)
    for (int dy = -int(g[1]); dy <= g[1]; ++dy)
      for (int dx = -int(g[0]); dx <= g[0]; ++dx) {
        if (!dx && !dy && !dz) continue;
        const int d[3] = {dx, dy, dz};
        coupler::Index3 probe{};
        if (!beyond(dec, b, d, probe)) continue;
        Neighbour n;
        n.rank = dec.owner(probe);
        for (int a = 0; a < 3; ++a) {
          const long e = b.extent(a), w = ghost[a];
          n.d[a] = d[a];
          n.send.lo[a] = d[a] > 0 ? e - w : 0;
          n.send.hi[a] = d[a] < 0 ? w : e;
          n.recv.lo[a] = d[a] < 0 ? -w : d[a] > 0 ? e : 0;
          n.recv.hi[a] = d[a] < 0 ? 0 : d[a] > 0 ? e + w : e;
          n.period[a] = d[a] * e;
        }
        out.push_back(n);
      }
  return out;
}

}  // namespace coflow::fluid::grid
