#include "immersed/psm/fractions.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <functional>
#include <numbers>
#include <utility>

namespace coflow::immersed {

using V = std::array<double, 3>;

double cube_fraction(const V& lo, double h, const V& c, double r, int levels) {
  // Nearest and farthest points of the cube from the centre.
  double near2 = 0.0, far2 = 0.0;
  for (int d = 0; d < 3; ++d) {
    const double a = lo[d] - c[d], b = lo[d] + h - c[d];
    const double n = a > 0 ? a : (b < 0 ? b : 0.0);
    const double f = std::max(std::abs(a), std::abs(b));
    near2 += n * n;
    far2 += f * f;
  }
  const double r2 = r * r;
  if (near2 >= r2) return 0.0;
  if (far2 <= r2) return 1.0;
  if (levels == 0) {
    double m2 = 0.0;
    for (int d = 0; d < 3; ++d) m2 += (lo[d] + 0.5 * h - c[d]) * (lo[d] + 0.5 * h - c[d]);
    return m2 < r2 ? 1.0 : 0.0;
  }
  const double hh = 0.5 * h;
  double sum = 0.0;
  for (int k = 0; k < 8; ++k) {
    const V sub{lo[0] + (k & 1) * hh, lo[1] + ((k >> 1) & 1) * hh, lo[2] + ((k >> 2) & 1) * hh};
    sum += cube_fraction(sub, hh, c, r, levels - 1);
  }
  return 0.125 * sum;
}

SphereFractions::SphereFractions(double h, const V& lower, int levels, int lattice,
                                 std::vector<double> kept_radii, std::size_t max_bytes, int blend_steps)
    : h_(h),
      lower_(lower),
      levels_(levels),
      lattice_(lattice),
      blend_steps_(blend_steps),
      kept_radii_(std::move(kept_radii)),
      max_bytes_(max_bytes) {}

std::size_t SphereFractions::KeyHash::operator()(const Key& k) const {
  std::size_t s = std::hash<std::uint64_t>{}(k.radius_bits);
  for (int v : {k.a, k.b, k.c}) s = s * 1000003u ^ std::hash<int>{}(v);
  return s;
}

// Every cell of the box, in cell units, then the cut cells scaled so that the
// sphere's cells add up to its volume exactly (wholly covered cells stay 1).
std::vector<double> SphereFractions::stencil(const V& offset, double r, int m) const {
  std::vector<double> f = octree_stencil(offset, r, m);
  renormalise(f, r);
  return f;
}

std::vector<double> SphereFractions::octree_stencil(const V& offset, double r, int m) const {
  const int n = 2 * m + 1;
  std::vector<double> f(static_cast<std::size_t>(n) * n * n, 0.0);
  std::size_t at = 0;
  for (int k = -m; k <= m; ++k)
    for (int j = -m; j <= m; ++j)
      for (int i = -m; i <= m; ++i, ++at)
        f[at] = cube_fraction({double(i), double(j), double(k)}, 1.0, offset, r, levels_);
  return f;
}

void SphereFractions::renormalise(std::vector<double>& f, double r) {
  double full = 0.0, cut = 0.0;
  for (const double v : f) (v >= 1.0 ? full : cut) += v;
  const double volume = 4.0 / 3.0 * std::numbers::pi * r * r * r;
  const double scale = cut > 0.0 ? (volume - full) / cut : 1.0;
  for (double& v : f)
    if (v > 0.0 && v < 1.0) v = std::min(1.0, v * scale);
}

// Offset a / N along an axis and (N - a) / N are mirror images (the cell i of
// one is the cell -i of the other), and the axes may be taken in any order:
// the class's stencil at offsets c0 <= c1 <= c2 <= N / 2, computed once,
// read back through the mirror and the permutation. With N a power of two the
// octree's coordinates, squares and sums are exact binary fractions, so the
// numbers are those of a direct computation (tests/unit/immersed).
std::vector<double> SphereFractions::by_symmetry(double r, int m, int a, int b, int c) {
  const int N = lattice_, want[3] = {a, b, c};
  int folded[3], order[3] = {0, 1, 2};
  bool mirror[3];
  for (int d = 0; d < 3; ++d) {
    mirror[d] = want[d] > N - want[d];
    folded[d] = mirror[d] ? N - want[d] : want[d];
  }
  std::stable_sort(order, order + 3, [&](int x, int y) { return folded[x] < folded[y]; });
  const Key key{std::bit_cast<std::uint64_t>(r), folded[order[0]], folded[order[1]], folded[order[2]]};
  auto it = classes_.find(key);
  if (it == classes_.end()) {
    const double s = 1.0 / N;
    it = classes_.emplace(key, octree_stencil({key.a * s, key.b * s, key.c * s}, r, m)).first;
    bytes_ += it->second.size() * sizeof(double);
    class_bytes_ += it->second.size() * sizeof(double);
    ++octree_;
  }
  const std::vector<double>& cls = it->second;
  const int n = 2 * m + 1;
  std::vector<double> f(cls.size());
  std::size_t at = 0;
  int x[3];
  for (x[2] = -m; x[2] <= m; ++x[2])
    for (x[1] = -m; x[1] <= m; ++x[1])
      for (x[0] = -m; x[0] <= m; ++x[0], ++at) {
        int i[3];  // the class's cell: axis e of the class is axis order[e] here
        for (int e = 0; e < 3; ++e) i[e] = (mirror[order[e]] ? -x[order[e]] : x[order[e]]) + m;
        f[at] = cls[(static_cast<std::size_t>(i[2]) * n + i[1]) * n + i[0]];
      }
  return f;
}

const std::vector<double>& SphereFractions::kept(double r, int m, int a, int b, int c) {
  const Key key{std::bit_cast<std::uint64_t>(r), a, b, c};
  auto it = kept_.find(key);
  if (it != kept_.end()) return it->second;
  if (bytes_ > max_bytes_) {  // a pure function of the key: dropping them changes no result
    kept_.clear();
    direct_.clear();  // its tables pointed into kept_
    if (class_bytes_ > max_bytes_ / 2) classes_.clear(), class_bytes_ = 0;
    bytes_ = class_bytes_;
  }
  const double s = 1.0 / lattice_;
  // Exact binary arithmetic (by_symmetry): a 2^k lattice, and leaves of 2^-levels whose squares and sums
  // stay within a double's 53 bits.
  const bool binary = std::has_single_bit(static_cast<unsigned>(lattice_)) && levels_ < 16;
  std::vector<double> f = binary ? by_symmetry(r, m, a, b, c) : octree_stencil({a * s, b * s, c * s}, r, m);
  if (!binary) ++octree_;
  renormalise(f, r);
  bytes_ += f.size() * sizeof(double);
  ++computed_;
  return kept_.emplace(key, std::move(f)).first->second;
}

const std::vector<double>& SphereFractions::kept_direct(double r, int m, int a, int b, int c) {
  const std::uint64_t bits = std::bit_cast<std::uint64_t>(r);
  const std::size_t n1 = static_cast<std::size_t>(lattice_) + 1;
  const std::size_t at =
      (static_cast<std::size_t>(a) * n1 + static_cast<std::size_t>(b)) * n1 + static_cast<std::size_t>(c);
  for (const Direct& d : direct_)
    if (d.radius_bits == bits && d.stencil[at]) return *d.stencil[at];
  const std::vector<double>& s = kept(r, m, a, b, c);  // map elements keep their address until a clear
  auto d =
      std::find_if(direct_.begin(), direct_.end(), [&](const Direct& x) { return x.radius_bits == bits; });
  if (d == direct_.end()) {
    d = direct_.insert(direct_.end(), Direct{bits, std::vector<const std::vector<double>*>(n1 * n1 * n1)});
    bytes_ += n1 * n1 * n1 * sizeof(const std::vector<double>*);
  }
  d->stencil[at] = &s;
  return s;
}

SphereFractions::Placement SphereFractions::place(const V& c, double radius) const {
  Placement p;
  p.radius_bits = std::bit_cast<std::uint64_t>(radius);
  V offset;
  for (int d = 0; d < 3; ++d) {
    const double x = (c[d] - lower_[d]) / h_;
    p.base[d] = static_cast<long>(std::floor(x));
    offset[d] = x - static_cast<double>(p.base[d]);
  }
  p.keep = lattice_ > 0 && std::any_of(kept_radii_.begin(), kept_radii_.end(),
                                       [&](double k) { return std::abs(k - radius) <= 1e-12 * k; });
  for (int d = 0; d < 3; ++d) {
    if (!p.keep) {
      p.at[d] = offset[d];
      continue;
    }
    const double u = offset[d] * lattice_;
    p.a0[d] = std::min(static_cast<int>(std::floor(u)), lattice_ - 1);
    const double t = u - p.a0[d];
    p.at[d] = blend_steps_ > 0 ? std::round(t * blend_steps_) / blend_steps_ : t;
  }
  return p;
}

void SphereFractions::cover(const V& c, double radius, Cells& out) {
  cover_at(place(c, radius), radius, out);
}

void SphereFractions::cover_at(const Placement& at, double radius, Cells& out) {
  const double r = radius / h_;
  const int m = static_cast<int>(std::ceil(r)) + 1;
  out.clear();
  if (at.keep) return blend(at, r, m, out);
  const std::vector<double> f = stencil({at.at[0], at.at[1], at.at[2]}, r, m);
  std::size_t i = 0;
  for (int z = -m; z <= m; ++z)
    for (int y = -m; y <= m; ++y)
      for (int x = -m; x <= m; ++x, ++i)
        if (f[i] > 0.0) out.push_back({{at.base[0] + x, at.base[1] + y, at.base[2] + z}, f[i]});
}

// The kept stencils of the eight lattice centres around the sphere's,
// weighted trilinearly.
void SphereFractions::blend(const Placement& at, double r, int m, Cells& out) {
  const int n = 2 * m + 1;
  int lo[3], hi[3];
  for (int d = 0; d < 3; ++d) {
    // The cells the corners' spheres can touch (their centres lie between
    // a0/N and (a0 + 1)/N): a smaller box than the stencils' own.
    lo[d] = std::max(-m, static_cast<int>(std::floor(double(at.a0[d]) / lattice_ - r)));
    hi[d] = std::min(m, static_cast<int>(std::floor(double(at.a0[d] + 1) / lattice_ + r)));
  }
  const int nx = hi[0] - lo[0] + 1, ny = hi[1] - lo[1] + 1, nz = hi[2] - lo[2] + 1;
  blend_.assign(static_cast<std::size_t>(nx) * ny * nz, 0.0);
  for (int corner = 0; corner < 8; ++corner) {
    double w = 1.0;
    for (int d = 0; d < 3; ++d) w *= (corner >> d & 1) ? at.at[d] : 1.0 - at.at[d];
    if (w <= 0.0) continue;
    const auto& s = kept_direct(r, m, at.a0[0] + (corner & 1), at.a0[1] + (corner >> 1 & 1),
                                at.a0[2] + (corner >> 2 & 1));
    double* b = blend_.data();
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j) {
        const double* row = s.data() + ((static_cast<std::size_t>(k + m) * n + (j + m)) * n + (lo[0] + m));
        for (int i = 0; i < nx; ++i) *b++ += w * row[i];
      }
  }
  std::size_t i = 0;
  for (int k = lo[2]; k <= hi[2]; ++k)
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int x = lo[0]; x <= hi[0]; ++x, ++i)
        if (blend_[i] > 0.0)
          out.push_back({{at.base[0] + x, at.base[1] + j, at.base[2] + k}, std::min(1.0, blend_[i])});
}

const SphereFractions::Cells& SphereFractions::cover_of(std::int64_t id, const V& c, double radius) {
  const Placement at = place(c, radius);
  ++asked_;
  auto it = lists_.find(id);
  if (it != lists_.end() && it->second.where == at && !it->second.cells.empty()) {
    it->second.asked = round_;
    ++reused_;
    return it->second.cells;
  }
  // A new sphere when the lists fill their memory: computed, not kept.
  if (it == lists_.end() && list_bytes_ >= max_bytes_) {
    cover_at(at, radius, spare_);
    return spare_;
  }
  if (it == lists_.end()) {
    it = lists_.emplace(id, Kept{}).first;
    list_bytes_ += kListOverhead;
  }
  Kept& k = it->second;
  const std::size_t before = k.cells.capacity();
  k.where = at;
  k.asked = round_;
  cover_at(at, radius, k.cells);
  list_bytes_ += (k.cells.capacity() - before) * sizeof(Cells::value_type);
  return k.cells;
}

void SphereFractions::forget_unasked() {
  // A pure memo: dropping a list changes no result.
  std::erase_if(lists_, [this](const auto& e) {
    if (e.second.asked == round_) return false;
    list_bytes_ -= kListOverhead + e.second.cells.capacity() * sizeof(Cells::value_type);
    return true;
  });
  ++round_;
}

}  // namespace coflow::immersed
