#include "fluid/fv/amr/composite_grid.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace coflow::fluid::fv::amr {
namespace {

constexpr int kBits = 19;  // per axis in a leaf key: 2^19 patches per level and axis

unsigned long long key(int level, const Index3& p) {
  const unsigned long long m = (1ULL << kBits) - 1;
  return (static_cast<unsigned long long>(level) << (3 * kBits)) |
         ((static_cast<unsigned long long>(p[2]) & m) << (2 * kBits)) |
         ((static_cast<unsigned long long>(p[1]) & m) << kBits) | (static_cast<unsigned long long>(p[0]) & m);
}

}  // namespace

CompositeGrid::CompositeGrid(const Forest& forest, const GridGeometry& geometry)
    : forest_(forest), geometry_(geometry), dims_(forest.spec().dims), n_(forest.spec().patch) {
  cells_per_patch_ = static_cast<long>(n_) * n_ * (dims_ == 3 ? n_ : 1);
  for (int d = 0; d < 3; ++d)
    if ((static_cast<long>(forest.spec().trees[d]) << forest.spec().max_level) >= (1L << kBits))
      throw std::invalid_argument("refinement: too many patches per axis on the finest level");
  for (const auto* list : {&forest.leaves(), &forest.ghosts()})
    for (const auto& leaf : *list) known_[key(leaf.level, leaf.patch)] = &leaf;
  for (std::size_t g = 0; g < forest.ghosts().size(); ++g)
    ghost_index_[forest.ghosts()[g].global] = static_cast<long>(g);
}

long CompositeGrid::slot(long id) const {
  const long leaf = id / cells_per_patch_, within = id % cells_per_patch_;
  const long local = leaf - forest_.first_leaf();
  if (local >= 0 && local < static_cast<long>(forest_.leaves().size()))
    return local * cells_per_patch_ + within;
  const auto it = ghost_index_.find(leaf);
  if (it == ghost_index_.end())
    throw std::logic_error("refinement: a stencil reaches beyond the ghost layer");
  return local_cells() + it->second * cells_per_patch_ + within;
}

bool CompositeGrid::locate(std::array<double, 3> x, long* local) const {
  // Inside the domain's bounding range, or no cell (a point not finite, or
  // far out, would give an index whose cast is undefined).
  const double reach = spacing(0) * static_cast<double>(forest_.spec().patch) * (1L << 20);
  for (int d = 0; d < dims_; ++d)
    if (!(std::abs(x[d] - geometry_.origin[d]) < reach)) return false;
  for (int level = forest_.spec().max_level; level >= 0; --level) {
    const double h = spacing(level);
    Index3 index{0, 0, 0};
    for (int d = 0; d < dims_; ++d)
      index[d] = static_cast<long>(std::floor((x[d] - geometry_.origin[d]) / h));
    long id = 0;
    if (cover(level, index, &id) != Cover::leaf) continue;
    const long c = id - first_cell();
    if (c < 0 || c >= local_cells()) return false;
    *local = c;
    return true;
  }
  return false;
}

Stencil CompositeGrid::to_slots(const Stencil& s) const {
  Stencil out;
  out.reserve(s.size());
  for (const auto& [id, w] : s) out.emplace_back(slot(id), w);
  return out;
}

void CompositeGrid::gather(int component, std::vector<double>& out) const {
  out.resize(static_cast<std::size_t>(slots()));
  const auto nc = static_cast<std::size_t>(forest_.spec().components);
  const auto per = static_cast<std::size_t>(cells_per_patch_);
  std::size_t k = 0;
  for (std::size_t l = 0; l < forest_.leaves().size(); ++l)
    for (std::size_t c = 0; c < per; ++c)
      out[k++] = forest_.data(l)[c * nc + static_cast<std::size_t>(component)];
  for (std::size_t g = 0; g < forest_.ghosts().size(); ++g)
    for (std::size_t c = 0; c < per; ++c)
      out[k++] = forest_.ghost_data(g)[c * nc + static_cast<std::size_t>(component)];
}

CompositeGrid::Cell CompositeGrid::local_cell(long c) const {
  const auto& leaf = forest_.leaves()[static_cast<std::size_t>(c / cells_per_patch_)];
  const long r = c % cells_per_patch_;
  const Index3 in{r % n_, (r / n_) % n_, r / (static_cast<long>(n_) * n_)};
  Cell cell{leaf.level, {0, 0, 0}};
  for (int d = 0; d < dims_; ++d) cell.index[d] = leaf.patch[d] * n_ + in[d];
  return cell;
}

std::array<double, 3> CompositeGrid::centre(const Cell& c) const {
  const double h = spacing(c.level);
  std::array<double, 3> x = geometry_.origin;
  for (int d = 0; d < dims_; ++d) x[d] += (static_cast<double>(c.index[d]) + 0.5) * h;
  return x;
}

long CompositeGrid::extent(int level, int axis) const {
  if (axis >= dims_) return 1;
  return (static_cast<long>(forest_.spec().trees[axis]) * n_) << level;
}

bool CompositeGrid::wrap(int level, Index3& index) const {
  for (int d = 0; d < dims_; ++d) {
    const long e = extent(level, d);
    if (index[d] >= 0 && index[d] < e) continue;
    if (!forest_.spec().periodic[d]) return false;
    index[d] = ((index[d] % e) + e) % e;
  }
  return true;
}

const Leaf* CompositeGrid::find(int level, const Index3& patch) const {
  const auto it = known_.find(key(level, patch));
  return it == known_.end() ? nullptr : it->second;
}

CompositeGrid::Cover CompositeGrid::cover(int level, Index3 index, long* id) const {
  if (!wrap(level, index)) return Cover::outside;
  for (int l = level; l >= 0; --l) {
    Index3 cell{0, 0, 0}, patch{0, 0, 0};
    for (int d = 0; d < dims_; ++d) {
      cell[d] = index[d] >> (level - l);
      patch[d] = cell[d] / n_;
    }
    const Leaf* leaf = find(l, patch);
    if (!leaf) continue;
    if (l < level) return Cover::coarser;
    if (id) {
      long local = 0;
      for (int d = dims_ - 1; d >= 0; --d) local = local * n_ + (cell[d] - patch[d] * n_);
      *id = leaf->global * cells_per_patch_ + local;
    }
    return Cover::leaf;
  }
  return Cover::finer;
}

bool CompositeGrid::value(int level, const Index3& index, Stencil& out, double weight) const {
  long id = 0;
  switch (cover(level, index, &id)) {
    case Cover::leaf:
      out.emplace_back(id, weight);
      return true;
    case Cover::finer: {
      if (level >= forest_.spec().max_level)
        throw std::logic_error("refinement: a cell's finer neighbours are not in this rank's ghost layer");
      const int children = 1 << dims_;
      for (int c = 0; c < children; ++c) {
        Index3 child{0, 0, 0};
        for (int d = 0; d < dims_; ++d) child[d] = 2 * index[d] + ((c >> d) & 1);
        if (!value(level + 1, child, out, weight / children))
          throw std::logic_error("refinement: the forest is not 2:1 balanced");
      }
      return true;
    }
    default:
      return false;
  }
}

void CompositeGrid::coarse_fine_gradient(const Cell& fine, int axis, int side, Stencil& out) const {
  // Normal to the face, in fine spacings from it: fine cells at -1.5 and
  // -0.5, the coarse value (interpolated along the face) at +1, the ghost at
  // +0.5; Lagrange weights -1/5, 2/3, 8/15. Gradient * h = ghost - phi_0.
  if (!value(fine.level, shifted(fine.index, axis, -side), out, -0.2) ||
      !value(fine.level, fine.index, out, -1.0 / 3.0))
    throw std::logic_error("refinement: a fine cell at a coarse-fine face lacks its inner neighbour");
  Index3 g = shifted(fine.index, axis, side);
  if (!wrap(fine.level, g)) throw std::logic_error("refinement: a coarse-fine face on a wall");
  Cell coarse{fine.level - 1, {0, 0, 0}};
  for (int d = 0; d < dims_; ++d) coarse.index[d] = g[d] >> 1;
  coarse_value_along_face(coarse, fine, axis, out, 8.0 / 15.0);
}

double CompositeGrid::quadratic_along(int lc, const Index3& c, int t, double dl, Stencil& out,
                                      double w) const {
  // Lagrange weights at offset dl from the centre node: central (nodes -1, 0,
  // 1) where both neighbours have values, else one-sided (0, 1, 2 or 0, -1,
  // -2); constant where neither. Returns the centre's weight minus one.
  Stencil a, b;
  if (value(lc, shifted(c, t, -1), a) && value(lc, shifted(c, t, 1), b)) {
    add(out, a, w * dl * (dl - 1.0) / 2.0);
    add(out, b, w * dl * (dl + 1.0) / 2.0);
    return -dl * dl;
  }
  for (int s : {1, -1}) {
    a.clear();
    b.clear();
    if (value(lc, shifted(c, t, s), a) && value(lc, shifted(c, t, 2 * s), b)) {
      const double x = s * dl;  // offset towards the side used
      add(out, a, w * -x * (x - 2.0));
      add(out, b, w * x * (x - 1.0) / 2.0);
      return (x - 1.0) * (x - 2.0) / 2.0 - 1.0;
    }
  }
  return 0.0;
}

void CompositeGrid::coarse_value_along_face(const Cell& coarse, const Cell& fine, int axis, Stencil& out,
                                            double w) const {
  const int lc = coarse.level;
  double centre = 1.0;
  std::array<double, 3> delta{0.0, 0.0, 0.0};
  std::array<int, 3> tangential{-1, -1, -1};
  int nt = 0;
  for (int t = 0; t < dims_; ++t) {
    if (t == axis) continue;
    tangential[nt++] = t;
    // Fine index 2m sits in the lower half of coarse cell m: offset -1/4.
    const double dl = (fine.index[t] & 1) ? 0.25 : -0.25;
    delta[t] = dl;
    centre += quadratic_along(lc, coarse.index, t, dl, out, w);
  }
  if (nt == 2) {  // the cross term d1 d2 phi_12 (3D), where all four corners have values
    const int t1 = tangential[0], t2 = tangential[1];
    Stencil corners;
    bool all = true;
    for (int s1 : {-1, 1})
      for (int s2 : {-1, 1})
        all = all && value(lc, shifted(shifted(coarse.index, t1, s1), t2, s2), corners, s1 * s2 * 0.25);
    if (all) add(out, corners, w * delta[t1] * delta[t2]);
  }
  long id = 0;
  if (cover(lc, coarse.index, &id) != Cover::leaf)
    throw std::logic_error("refinement: levels differ by more than one");
  out.emplace_back(id, w * centre);
}

}  // namespace coflow::fluid::fv::amr
