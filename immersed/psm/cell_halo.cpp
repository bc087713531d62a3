#include "immersed/psm/cell_halo.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "particles/store/domain.hpp"

namespace coflow::immersed::psm {

using coupler::Box;
using coupler::Index3;

CellHalo::CellHalo(MPI_Comm comm, const coupler::Decomposition& dec, int rank, int width)
    : comm_(comm), size_(dec.ranks()), cells_(dec.cells()), out_(static_cast<std::size_t>(dec.ranks())) {
  const Box& mine = dec.block(rank);
  const Index3 g = dec.ghost(width);
  for (int r = 0; r < size_; ++r) {
    if (r == rank) continue;
    // The other rank's grown block, at each periodic image, seen from here.
    for (const Index3& sh : dec.image_shifts()) {
      const Box part = coupler::intersect(mine, dec.block(r).grown(g).shifted(sh));
      if (!part.empty()) reach_.emplace_back(r, part);
    }
  }
}

void CellHalo::exchange(std::span<const Index3> cells, std::span<const double> values, int per_cell) {
  if (values.size() != cells.size() * static_cast<std::size_t>(per_cell))
    throw std::logic_error("psm cell halo: values and cells differ in count");
  per_cell_ = per_cell;
  at_.clear();
  in_.clear();
  if (size_ == 1) return;
  for (auto& o : out_) o.clear();
  for (std::size_t n = 0; n < cells.size(); ++n) {
    int last = -1;  // a rank reached through two images gets the cell once
    for (const auto& [r, part] : reach_) {
      if (r == last || !part.contains(cells[n])) continue;
      last = r;
      auto& o = out_[static_cast<std::size_t>(r)];
      o.push_back(static_cast<double>(linear(cells[n])));  // exact below 2^53 cells
      o.insert(o.end(), values.begin() + static_cast<long>(n) * per_cell,
               values.begin() + static_cast<long>(n + 1) * per_cell);
    }
  }
  particles::store::exchange(comm_, out_, in_);
  const std::size_t stride = 1 + static_cast<std::size_t>(per_cell);
  at_.reserve(in_.size() / stride);
  for (std::size_t k = 0; k + stride <= in_.size(); k += stride)
    at_.emplace(static_cast<long>(in_[k]), k + 1);
}

const double* CellHalo::find(const Index3& cell) const {
  const auto it = at_.find(linear(cell));
  return it == at_.end() ? nullptr : &in_[it->second];
}

}  // namespace coflow::immersed::psm
