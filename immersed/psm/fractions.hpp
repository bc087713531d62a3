// Solid fractions of the cells a sphere covers, for psm (seed 000 §2.4: each
// cell's share of solid, eq. 2.66's epsilon).
//
// cube_fraction is the octree estimate of one cell. SphereFractions covers a
// whole sphere, renormalised so that its cells add up to its volume exactly,
// in one of two ways:
//   - exact centre (lattice 0): every cell's octree at the sphere's own
//     centre, every window; the reference;
//   - centre lattice N (the default), for the radii it is given (the
//     species of fixed diameter; other radii, from a size distribution or
//     crushing, take the exact centre, as kept stencils of radii that never
//     repeat would cost more than they save): the fractions depend only on the
//     radius and the centre's offset inside its cell, so they are computed once for
//     the centres on a lattice of h/N in the cell, kept, and interpolated
//     trilinearly to the actual offset. A sphere that moves costs a few
//     multiply-adds per cell instead of an octree per cut cell; whole-cell
//     moves shift the kept stencils. Each kept stencil sums to the volume, so
//     the interpolation does too; the difference from the exact centre is below
//     the octree's own error (tests/unit/immersed/test_psm_fractions.cpp).
//     The interpolation's weights are rounded to multiples of 1 / M
//     (`blend_steps`; 128: the interpolation taken at a centre moved by at
//     most h / 2048 at N = 8), so that a sphere whose rounded placement has
//     not changed since the last window, as for most grains of a packed bed,
//     keeps its cells (cover_of) instead of blending them again.
// Both are pure functions of the centre and radius, so a restart and any
// number of ranks give the same bits.
#pragma once

#include <array>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "coflow/decomposition.hpp"

namespace coflow::immersed {

// Fraction of the cube [lo, lo + h]^3 inside the sphere (c, r): exact 0 or 1
// when the cube is wholly outside or inside, otherwise the cube is split into 8
// down to `levels` times and each undecided leaf counts by its centre.
double cube_fraction(const std::array<double, 3>& lo, double h, const std::array<double, 3>& c, double r, int levels);

class SphereFractions {
 public:
  // h: the cell size; lower: the grid's origin; levels: octree levels;
  // lattice: centre positions per cell and axis (0: exact centres);
  // kept_radii: the radii (m) whose stencils are kept; max_bytes: the kept
  // stencils' memory (their lookup tables counted). When it is passed the
  // kept stencils and their tables are dropped, and the symmetry classes'
  // octree stencils (the costly ones, 35 a radius at N = 8) only when they
  // alone take half of it.
  // blend_steps: the interpolation's weights rounded to multiples of
  // 1 / blend_steps (0: not rounded).
  SphereFractions(double h, const std::array<double, 3>& lower, int levels, int lattice,
                  std::vector<double> kept_radii, std::size_t max_bytes = std::size_t{256} << 20,
                  int blend_steps = 0);
  // Not copied: the lookup tables point into this object's kept stencils.
  SphereFractions(const SphereFractions&) = delete;
  SphereFractions& operator=(const SphereFractions&) = delete;

  // The cells (global, unwrapped indices) sphere (c, r) covers and their
  // fractions (> 0), replacing `out`'s contents.
  using Cells = std::vector<std::pair<coupler::Index3, double>>;
  void cover(const std::array<double, 3>& c, double r, Cells& out);
  // The same for the sphere `id`, kept from its last call while its placement
  // (base cell, lattice offsets and rounded weights; its exact centre where
  // it keeps no stencils) and radius stay the same: cover() would compute
  // the same list again, to the bit. The reference is valid until the next
  // call. The kept lists have a budget of max_bytes of their own: when it is
  // spent, spheres without a list get theirs computed and not kept.
  const Cells& cover_of(std::int64_t id, const std::array<double, 3>& c, double r);
  // Drops the lists of the spheres not asked for since the last call.
  void forget_unasked();

  std::size_t stencils_computed() const { return computed_; }
  // cover_of's calls that found the sphere's list kept, and all its calls.
  std::size_t lists_reused() const { return reused_; }
  std::size_t lists_asked() const { return asked_; }
  // The stencils computed by the octree: on a lattice of 2^k offsets a kept
  // stencil is its symmetry class's (offset a or N - a per axis, axes in any
  // order: 35 classes of 729 offsets at N = 8) mirrored and permuted, the
  // same numbers (the octree's arithmetic is exact on such offsets).
  std::size_t octree_stencils() const { return octree_; }

 private:
  struct Key {
    std::uint64_t radius_bits;
    int a, b, c;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const;
  };
  // Where a sphere's fractions come from: its base cell and either its
  // offset in it (exact centre) or the lattice offsets a0 and the weights t
  // between them (kept stencils). Equal placements give equal fractions.
  struct Placement {
    std::uint64_t radius_bits = 0;
    long base[3] = {0, 0, 0};
    bool keep = false;
    int a0[3] = {0, 0, 0};
    double at[3] = {0, 0, 0};  // exact centre: the offset in cells; kept: the weights t
    bool operator==(const Placement&) const = default;
  };
  struct Kept {
    Placement where;
    Cells cells;
    std::size_t asked = 0;  // the round (forget_unasked) it was last asked in
  };
  Placement place(const std::array<double, 3>& c, double radius) const;
  void cover_at(const Placement& at, double radius, Cells& out);
  void blend(const Placement& at, double r, int m, Cells& out);
  // The fractions in the (2m+1)^3 cells around a base cell of a sphere of
  // radius r (in cells) whose centre is `offset` (in cells) from the base
  // cell's lower corner, renormalised to the sphere's volume.
  std::vector<double> stencil(const std::array<double, 3>& offset, double r, int m) const;
  // The same before the renormalisation (octree fractions), and that step.
  std::vector<double> octree_stencil(const std::array<double, 3>& offset, double r, int m) const;
  static void renormalise(std::vector<double>& f, double r);
  const std::vector<double>& kept(double r, int m, int a, int b, int c);
  // kept() through a table per radius, indexed by the lattice offset (the
  // blend asks for eight stencils a sphere: no hashing).
  const std::vector<double>& kept_direct(double r, int m, int a, int b, int c);
  // The octree stencil at lattice offset (a, b, c) from its symmetry class's.
  std::vector<double> by_symmetry(double r, int m, int a, int b, int c);

  double h_;
  std::array<double, 3> lower_;
  int levels_, lattice_, blend_steps_;
  std::vector<double> kept_radii_;
  std::size_t max_bytes_, bytes_ = 0, class_bytes_ = 0, computed_ = 0, octree_ = 0;
  std::unordered_map<Key, std::vector<double>, KeyHash> kept_;
  std::unordered_map<Key, std::vector<double>, KeyHash> classes_;  // octree stencils of the symmetry classes
  std::vector<double> blend_;
  struct Direct {
    std::uint64_t radius_bits;
    std::vector<const std::vector<double>*> stencil;  // (N + 1)^3 offsets; null: not looked up yet
  };
  std::vector<Direct> direct_;  // emptied whenever kept() drops its stencils
  std::unordered_map<std::int64_t, Kept> lists_;  // cover_of's lists, by sphere
  static constexpr std::size_t kListOverhead = sizeof(Kept) + 4 * sizeof(void*);  // a map node, about
  Cells spare_;  // cover_of's list of a sphere it does not keep
  std::size_t list_bytes_ = 0, round_ = 0, reused_ = 0, asked_ = 0;
};

}  // namespace coflow::immersed
