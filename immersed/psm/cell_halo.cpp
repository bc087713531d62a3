#include "immersed/psm/cell_halo.hpp"

#include <limits>
#include <stdexcept>

#include "particles/store/domain.hpp"

namespace coflow::immersed::psm {

using coupler::Box;
using coupler::Index3;

CellHalo::CellHalo(MPI_Comm comm, const coupler::Decomposition& dec, int rank, int width)
    : comm_(comm),
      size_(dec.ranks()),
      cells_(dec.cells()),
      periodic_(dec.periodic()),
      shifts_(dec.image_shifts()),
      out_(static_cast<std::size_t>(dec.ranks())) {
  const Box& mine = dec.block(rank);
  const Index3 g = dec.ghost(width);
  inner_ = mine.grown({-g[0], -g[1], -g[2]});
  grown_ = mine.grown(g);
  if (size_ == 1) return;  // nothing to share
  for (int r = 0; r < size_; ++r) {
    if (r == rank) continue;
    // The other rank's grown block, at each periodic image, seen from here.
    for (const Index3& sh : shifts_) {
      const Box part = coupler::intersect(mine, dec.block(r).grown(g).shifted(sh));
      if (!part.empty()) reach_.emplace_back(r, part);
    }
  }
  if (grown_.volume() > std::numeric_limits<std::int32_t>::max())
    throw std::runtime_error(
        "psm: too many cells on one immersed rank for its halo; run immersed on more ranks");
  slot_.assign(static_cast<std::size_t>(grown_.volume()), -1);
}

long CellHalo::slot_index(const Index3& c) const {
  return ((c[2] - grown_.lo[2]) * grown_.extent(1) + (c[1] - grown_.lo[1])) * grown_.extent(0) +
         (c[0] - grown_.lo[0]);
}

void CellHalo::exchange(std::span<const Index3> cells, std::span<const double> values, int per_cell) {
  if (values.size() != cells.size() * static_cast<std::size_t>(per_cell))
    throw std::logic_error("psm cell halo: values and cells differ in count");
  if (size_ == 1) return;
  for (const long s : filled_) slot_[static_cast<std::size_t>(s)] = -1;
  filled_.clear();
  for (auto& o : out_) o.clear();
  for (std::size_t n = 0; n < cells.size(); ++n) {
    if (inner_.contains(cells[n])) continue;  // most cells: in no other rank's ghost layer
    int last = -1;                            // a rank reached through two images gets the cell once
    for (const auto& [r, part] : reach_) {
      if (r == last || !part.contains(cells[n])) continue;
      last = r;
      auto& o = out_[static_cast<std::size_t>(r)];
      const Index3& c = cells[n];
      o.push_back(
          static_cast<double>((c[2] * cells_[1] + c[1]) * cells_[0] + c[0]));  // exact below 2^53 cells
      o.insert(o.end(), values.begin() + static_cast<long>(n) * per_cell,
               values.begin() + static_cast<long>(n + 1) * per_cell);
    }
  }
  particles::store::exchange(comm_, out_, in_);
  const std::size_t stride = 1 + static_cast<std::size_t>(per_cell);
  if (in_.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    throw std::runtime_error(
        "psm: too many ghost cells reach one immersed rank for its halo; run immersed on more ranks");
  for (std::size_t k = 0; k + stride <= in_.size(); k += stride) {
    const long linear = static_cast<long>(in_[k]);
    const Index3 c{linear % cells_[0], (linear / cells_[0]) % cells_[1], linear / (cells_[0] * cells_[1])};
    for (const Index3& sh : shifts_) {  // every place it takes in the ghost layer
      const Index3 u{c[0] + sh[0], c[1] + sh[1], c[2] + sh[2]};
      if (!grown_.contains(u)) continue;
      const long s = slot_index(u);
      slot_[static_cast<std::size_t>(s)] = static_cast<std::int32_t>(k + 1);
      filled_.push_back(s);
    }
  }
}

const double* CellHalo::find(Index3 cell) const {
  if (size_ == 1) return nullptr;
  for (int d = 0; d < 3; ++d) {  // a centre not yet wrapped: its cells at the image next to this block
    if (!periodic_[d]) continue;
    while (cell[d] < grown_.lo[d]) cell[d] += cells_[d];
    while (cell[d] >= grown_.hi[d]) cell[d] -= cells_[d];
  }
  if (!grown_.contains(cell)) return nullptr;
  const std::int32_t at = slot_[static_cast<std::size_t>(slot_index(cell))];
  return at < 0 ? nullptr : &in_[static_cast<std::size_t>(at)];
}

}  // namespace coflow::immersed::psm
