// The body of a Forest engine, written with p4est's 2D names: forest_2d.cpp
// includes it as is, forest_3d.cpp after <p4est_to_p8est.h>, which renames
// every p4est_ call, type and constant to its p8est_ (octree) twin. This is
// p4est's own idiom for dimension-independent code.
//
// Expects, before inclusion: the p4est (or p8est) headers, and the macro
// COFLOW_FOREST_ENGINE naming the builder function.
#include <mpi.h>

#include <stdexcept>

#include "fluid/fv/amr/forest.hpp"

namespace coflow::fluid::fv::amr {
namespace {

struct BuildContext {
  const ForestSpec* spec;
  const p4est_connectivity_t* conn;
};

// A quadrant's patch index at its level over the whole brick.
Index3 patch_of(const p4est_connectivity_t* conn, p4est_topidx_t tree, const p4est_quadrant_t* q) {
  const double* v = conn->vertices + 3 * conn->tree_to_vertex[P4EST_CHILDREN * tree];
  const int shift = P4EST_MAXLEVEL - q->level;
  Index3 p{0, 0, 0};
  p[0] = (static_cast<long>(v[0]) << q->level) + (q->x >> shift);
  p[1] = (static_cast<long>(v[1]) << q->level) + (q->y >> shift);
#ifdef P4_TO_P8
  p[2] = (static_cast<long>(v[2]) << q->level) + (q->z >> shift);
#endif
  return p;
}

int refine_leaf(p4est_t* forest, p4est_topidx_t tree, p4est_quadrant_t* q) {
  const auto* ctx = static_cast<const BuildContext*>(forest->user_pointer);
  if (q->level >= ctx->spec->max_level) return 0;
  if (q->level < ctx->spec->min_level) return 1;
  return ctx->spec->refine && ctx->spec->refine(q->level, patch_of(ctx->conn, tree, q)) ? 1 : 0;
}

class Engine final : public Forest::Engine {
 public:
  Engine(MPI_Comm comm, const ForestSpec& spec) : spec_(spec) {
    if (spec.max_level > P4EST_QMAXLEVEL)
      throw std::invalid_argument("refinement: too many levels for p4est");
#ifdef P4_TO_P8
    conn_ = p8est_connectivity_new_brick(spec.trees[0], spec.trees[1], spec.trees[2], spec.periodic[0],
                                         spec.periodic[1], spec.periodic[2]);
#else
    conn_ = p4est_connectivity_new_brick(spec.trees[0], spec.trees[1], spec.periodic[0], spec.periodic[1]);
#endif
    forest_ = p4est_new_ext(comm, conn_, 0, spec.min_level, 1, 0, nullptr, nullptr);
    BuildContext ctx{&spec_, conn_};
    forest_->user_pointer = &ctx;
    p4est_refine(forest_, 1, refine_leaf, nullptr);
    p4est_balance(forest_, P4EST_CONNECT_FULL, nullptr);
    p4est_partition(forest_, 0, nullptr);
    forest_->user_pointer = nullptr;
    ghost_ = p4est_ghost_new(forest_, P4EST_CONNECT_FULL);
  }
  ~Engine() override {
    if (ghost_) p4est_ghost_destroy(ghost_);
    if (forest_) p4est_destroy(forest_);
    if (conn_) p4est_connectivity_destroy(conn_);
  }
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  void collect(Forest& f) override {
    auto& leaves = EngineAccess::leaves(f);
    auto& ghosts = EngineAccess::ghosts(f);
    leaves.clear();
    ghosts.clear();
    const long first = static_cast<long>(forest_->global_first_quadrant[forest_->mpirank]);
    for (p4est_topidx_t t = forest_->first_local_tree; t <= forest_->last_local_tree; ++t) {
      const auto* tree = p4est_tree_array_index(forest_->trees, t);
      for (size_t i = 0; i < tree->quadrants.elem_count; ++i) {
        const auto* q = p4est_quadrant_array_index(const_cast<sc_array_t*>(&tree->quadrants), i);
        leaves.push_back(
            {q->level, patch_of(conn_, t, q), first + static_cast<long>(leaves.size()), forest_->mpirank});
      }
    }
    for (int r = 0; r < forest_->mpisize; ++r)
      for (p4est_locidx_t g = ghost_->proc_offsets[r]; g < ghost_->proc_offsets[r + 1]; ++g) {
        const auto* q = p4est_quadrant_array_index(&ghost_->ghosts, static_cast<size_t>(g));
        const long global = static_cast<long>(forest_->global_first_quadrant[r]) + q->p.piggy3.local_num;
        ghosts.push_back({q->level, patch_of(conn_, q->p.piggy3.which_tree, q), global, r});
      }
    EngineAccess::counts(f, static_cast<long>(forest_->global_num_quadrants), first);
  }

 private:
  ForestSpec spec_;
  p4est_connectivity_t* conn_ = nullptr;
  p4est_t* forest_ = nullptr;
  p4est_ghost_t* ghost_ = nullptr;
};

}  // namespace

std::unique_ptr<Forest::Engine> COFLOW_FOREST_ENGINE(MPI_Comm comm, const ForestSpec& spec) {
  return std::make_unique<Engine>(comm, spec);
}

}  // namespace coflow::fluid::fv::amr
