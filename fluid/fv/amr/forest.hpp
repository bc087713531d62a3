// The refinement engine of fv's block-structured adaptive grid: a forest of
// quadtrees (2D) or octrees (3D) kept by p4est (Debian's libp4est-dev), one
// tree per unit block of a brick, 2:1 balanced across faces, edges and
// corners, partitioned over the ranks by equal leaf counts (every leaf holds
// a patch of the same number of cells), with one layer of ghost leaves from
// the neighbouring ranks. This class keeps p4est's objects and hands out the
// leaves as plain data; the cells, the operators and the fields live in
// composite_grid.hpp and the modules built on it.
//
// Why p4est: it is the distributed octree of deal.II, ForestClaw and
// waLBerla's users, with 2:1 balance, partitioning and ghost layers that a
// home-made tree would have to re-derive (docs/architecture.md).
#pragma once

#include <mpi.h>

#include <array>
#include <functional>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "coflow/decomposition.hpp"

namespace coflow::fluid::fv::amr {

using coupler::Index3;

// A leaf of the forest: a patch of cells at `level`. Its position is its
// index among all patches of that level over the whole brick (level 0: the
// tree's brick position; each level doubles the counts per axis).
struct Leaf {
  int level = 0;
  Index3 patch{0, 0, 0};
  long global = 0;  // its index in the forest's global order (Morton per tree)
  int owner = 0;    // the rank that owns it
};

struct ForestSpec {
  int dims = 2;                       // 2 or 3
  std::array<int, 3> trees{1, 1, 1};  // brick of unit trees (trees[2] = 1 in 2D)
  std::array<bool, 3> periodic{false, false, false};
  int min_level = 0;   // every leaf at least this fine
  int max_level = 0;   // no leaf finer
  int patch = 8;       // cells per patch edge (even, at least 4)
  int components = 0;  // field values per cell kept on the leaves (0: none)
  // Components from this one on are positive (k, epsilon, nu_t): refining
  // keeps them so (the transfer's slopes at a patch's edges are capped).
  int positive_from = 1 << 30;
  int values_per_leaf() const { return components * patch * patch * (dims == 3 ? patch : 1); }
  // Refine the leaf at (level, patch) once more? Asked for every leaf below
  // max_level, recursively; the forest is then 2:1 balanced, so a few
  // leaves may be finer than asked.
  std::function<bool(int level, const Index3& patch)> refine;
};

class Forest {
 public:
  Forest(MPI_Comm comm, const ForestSpec& spec);
  // A forest saved by save(), on any rank count (its leaves and values; the
  // spec must be the one it was built with: its refine function is not
  // called). Collective; every rank throws, naming the file, when a value
  // is not finite (a damaged checkpoint).
  Forest(MPI_Comm comm, const ForestSpec& spec, const std::string& path);
  // Writes the leaves and their values to one file (p4est's format). Collective.
  void save(const std::string& path) { engine_->save(path); }
  ~Forest();
  Forest(const Forest&) = delete;
  Forest& operator=(const Forest&) = delete;

  const ForestSpec& spec() const { return spec_; }
  const std::vector<Leaf>& leaves() const { return leaves_; }  // this rank's, in global order
  const std::vector<Leaf>& ghosts() const { return ghosts_; }  // neighbours' leaves touching ours
  // Leaf i's field values (patch cells x fastest, `components` per cell);
  // p4est moves them with the leaf when it repartitions.
  std::span<double> data(std::size_t leaf) {
    return {data_[leaf], static_cast<std::size_t>(spec_.values_per_leaf())};
  }
  std::span<const double> data(std::size_t leaf) const {
    return {data_[leaf], static_cast<std::size_t>(spec_.values_per_leaf())};
  }
  // Ghost leaf g's values, as of the last exchange_ghosts().
  std::span<const double> ghost_data(std::size_t g) const {
    const std::size_t stride = static_cast<std::size_t>(spec_.values_per_leaf()) + 1;
    if (ghost_buffer_.size() != ghosts_.size() * stride)
      throw std::logic_error("refinement: ghost values read before exchange_ghosts() after a regrid");
    return {ghost_buffer_.data() + g * stride, stride - 1};
  }
  void exchange_ghosts() { engine_->exchange(*this); }
  // Regrids: each local leaf's mark (+1 refine, -1 coarsen if its whole
  // family says so, 0 keep; levels stay within min_level..max_level), then
  // 2:1 balance and repartition. Field values follow conservatively: a
  // refined cell's children take a limited linear reconstruction of it (the
  // mean of the children is the parent's value), a coarsened cell the mean
  // of its children. Collective; returns whether any rank refined or
  // coarsened a leaf (balance included).
  bool adapt(const std::vector<int>& marks) {
    if (marks.size() != leaves_.size()) throw std::invalid_argument("refinement: one mark per local leaf");
    int changed = engine_->adapt(*this, marks) ? 1 : 0;
    MPI_Allreduce(MPI_IN_PLACE, &changed, 1, MPI_INT, MPI_MAX, comm_);
    return changed != 0;
  }
  long global_leaves() const { return global_leaves_; }
  long first_leaf() const { return first_leaf_; }  // global index of leaves()[0]
  MPI_Comm comm() const { return comm_; }

  // The p4est objects, 2D or 3D (forest_2d.cpp, forest_3d.cpp).
  struct Engine {
    virtual ~Engine() = default;
    virtual void collect(Forest& f) = 0;  // fill leaves_, ghosts_, data_, counts
    // Returns whether this rank refined or coarsened any leaf.
    virtual bool adapt(Forest& f, const std::vector<int>& marks) = 0;
    virtual void exchange(Forest& f) = 0;
    virtual void save(const std::string& path) = 0;
  };

 private:
  friend struct EngineAccess;
  void refuse_not_finite(const std::string& path) const;
  ForestSpec spec_;
  MPI_Comm comm_;
  std::unique_ptr<Engine> engine_;
  std::vector<Leaf> leaves_, ghosts_;
  std::vector<double*> data_;
  std::vector<double> ghost_buffer_;  // per ghost leaf its values and its mark
  long global_leaves_ = 0, first_leaf_ = 0;
};

// The dimension-specific builders (compiled once per dimension from
// forest_p4est_impl.hpp).
// An empty path builds a new forest; otherwise loads the saved one.
std::unique_ptr<Forest::Engine> make_forest_engine_2d(MPI_Comm comm, const ForestSpec& spec,
                                                      const std::string& path);
std::unique_ptr<Forest::Engine> make_forest_engine_3d(MPI_Comm comm, const ForestSpec& spec,
                                                      const std::string& path);

// Lets the engines fill a forest's leaf lists.
struct EngineAccess {
  static std::vector<Leaf>& leaves(Forest& f) { return f.leaves_; }
  static std::vector<Leaf>& ghosts(Forest& f) { return f.ghosts_; }
  static std::vector<double*>& data(Forest& f) { return f.data_; }
  static std::vector<double>& ghost_buffer(Forest& f) { return f.ghost_buffer_; }
  static void counts(Forest& f, long global, long first) {
    f.global_leaves_ = global;
    f.first_leaf_ = first;
  }
};

}  // namespace coflow::fluid::fv::amr
