// The body of a Forest engine, written with p4est's 2D names: forest_2d.cpp
// includes it as is, forest_3d.cpp after <p4est_to_p8est.h>, which renames
// every p4est_ call, type and constant to its p8est_ (octree) twin. This is
// p4est's own idiom for dimension-independent code.
//
// Expects, before inclusion: the p4est (or p8est) headers, and the macro
// COFLOW_FOREST_ENGINE naming the builder function.
#include <mpi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "fluid/fv/amr/forest.hpp"

namespace coflow::fluid::fv::amr {
namespace {

struct BuildContext {
  const ForestSpec* spec;
  const p4est_connectivity_t* conn;
  int values = 0;     // doubles of field data per leaf; one more holds the leaf's mark
  long replaced = 0;  // leaves refined or coarsened (by marks or by balance) this rank
};

// The cell of a parent patch that holds cell `cell` of its child `child`
// (p4est's child order: x bit first, then y, then z).
long parent_of(long cell, int child, int n, int dims) {
  long parent = 0, stride = 1;
  for (int d = 0; d < dims; ++d) {
    const long i = (cell / stride) % n;
    parent += ((i + ((child >> d) & 1) * n) / 2) * stride;
    stride *= n;
  }
  return parent;
}

double* data_of(p4est_quadrant_t* q) {
  return static_cast<double*>(q->p.user_data);
}

// New leaves start with zero data and no mark.
void zero_leaf(p4est_t* forest, p4est_topidx_t, p4est_quadrant_t* q) {
  const auto* ctx = static_cast<const BuildContext*>(forest->user_pointer);
  std::fill_n(data_of(q), ctx->values + 1, 0.0);
}

// The limited slope (per parent cell) of component q of a parent patch along
// `axis` at parent cell (i, j, k): minmod of the two one-sided differences
// inside the patch; at the patch's edges (no neighbour values in p4est's
// callback) the one-sided difference, unlimited, or for a positive component
// at most the centre's value (as minmod's slopes are: with a quarter cell's
// offset along each of at most 3 axes a child keeps a quarter of it).
double limited_slope(const double* parent, int n, int components, int q, const std::array<long, 3>& ijk,
                     int axis, bool positive) {
  auto at = [&](std::array<long, 3> c) { return parent[((c[2] * n + c[1]) * n + c[0]) * components + q]; };
  const double centre = at(ijk);
  std::array<long, 3> lo = ijk, hi = ijk;
  --lo[axis];
  ++hi[axis];
  const bool has_lo = lo[axis] >= 0, has_hi = hi[axis] < n;
  const double down = has_lo ? centre - at(lo) : 0.0, up = has_hi ? at(hi) - centre : 0.0;
  auto capped = [&](double s) { return positive ? std::clamp(s, -centre, centre) : s; };
  if (!has_lo) return capped(up);
  if (!has_hi) return capped(down);
  if (down * up <= 0.0) return 0.0;
  return std::fabs(down) < std::fabs(up) ? down : up;
}

// Conservative transfer. A refined leaf's children take a limited linear
// reconstruction of their parent cell (value + slope x offset, offsets of a
// quarter cell either way, so the children's mean is the parent's value;
// no new extrema inside the patch); a coarsened family's parent takes the mean of
// the 2^d child cells over each of its cells.
void refine_cells(const BuildContext& ctx, const double* parent, double* child, int which) {
  const int n = ctx.spec->patch, dims = ctx.spec->dims, components = ctx.spec->components;
  const long per = ctx.values / components;
  for (long cell = 0; cell < per; ++cell) {
    std::array<long, 3> p{0, 0, 0};
    std::array<double, 3> offset{0.0, 0.0, 0.0};
    long rest = cell;
    for (int d = 0; d < dims; ++d) {
      const long i = rest % n + ((which >> d) & 1) * n;  // in the parent's fine units
      rest /= n;
      p[static_cast<std::size_t>(d)] = i / 2;
      offset[static_cast<std::size_t>(d)] = (i % 2) ? 0.25 : -0.25;
    }
    const long parent_cell = (p[2] * n + p[1]) * n + p[0];
    for (int q = 0; q < components; ++q) {
      double v = parent[parent_cell * components + q];
      for (int d = 0; d < dims; ++d)
        v += offset[static_cast<std::size_t>(d)] *
             limited_slope(parent, n, components, q, p, d, q >= ctx.spec->positive_from);
      child[cell * components + q] = v;
    }
  }
  child[ctx.values] = 0.0;
}

void transfer(p4est_t* forest, p4est_topidx_t, int n_out, p4est_quadrant_t* out[], int n_in,
              p4est_quadrant_t* in[]) {
  auto* ctx = static_cast<BuildContext*>(forest->user_pointer);
  ++ctx->replaced;
  if (ctx->values == 0) return;
  const int n = ctx->spec->patch, dims = ctx->spec->dims;
  const long per = ctx->values / ctx->spec->components;  // cells per patch
  const int components = ctx->spec->components;
  if (n_out == 1) {  // refined: parent out[0], children in[0..2^d)
    for (int c = 0; c < n_in; ++c) refine_cells(*ctx, data_of(out[0]), data_of(in[c]), c);
  } else {  // coarsened: children out[0..2^d), parent in[0]
    double* parent = data_of(in[0]);
    std::fill_n(parent, ctx->values + 1, 0.0);
    const double w = 1.0 / n_out;
    for (int c = 0; c < n_out; ++c)
      for (long cell = 0; cell < per; ++cell) {
        const long parent_cell = parent_of(cell, c, n, dims);
        for (int q = 0; q < components; ++q)
          parent[parent_cell * components + q] += w * data_of(out[c])[cell * components + q];
      }
  }
}

int refine_marked(p4est_t* forest, p4est_topidx_t, p4est_quadrant_t* q) {
  const auto* ctx = static_cast<const BuildContext*>(forest->user_pointer);
  return q->level < ctx->spec->max_level && data_of(q)[ctx->values] > 0.5 ? 1 : 0;
}

int coarsen_marked(p4est_t* forest, p4est_topidx_t, p4est_quadrant_t* family[]) {
  const auto* ctx = static_cast<const BuildContext*>(forest->user_pointer);
  if (family[0]->level <= ctx->spec->min_level) return 0;
  for (int c = 0; c < P4EST_CHILDREN; ++c)
    if (!(data_of(family[c])[ctx->values] < -0.5)) return 0;
  return 1;
}

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
    ctx_ = {&spec_, conn_, spec.values_per_leaf()};
    const auto bytes = static_cast<size_t>(ctx_.values + 1) * sizeof(double);
    forest_ = p4est_new_ext(comm, conn_, 0, spec.min_level, 1, bytes, zero_leaf, &ctx_);
    p4est_refine(forest_, 1, refine_leaf, zero_leaf);
    p4est_balance(forest_, P4EST_CONNECT_FULL, zero_leaf);
    // Families stay on one rank, so that any family can be coarsened later
    // whatever the rank count (1 rank then equals N).
    p4est_partition(forest_, 1, nullptr);
    ghost_ = p4est_ghost_new(forest_, P4EST_CONNECT_FULL);
  }
  // Loads a forest saved by save() (any rank count), partitioned as a run of
  // this rank count would have it.
  Engine(MPI_Comm comm, const ForestSpec& spec, const std::string& path) : spec_(spec) {
    ctx_ = {&spec_, nullptr, spec.values_per_leaf()};
    const auto bytes = static_cast<size_t>(ctx_.values + 1) * sizeof(double);
    forest_ = p4est_load_ext(path.c_str(), comm, bytes, 1, 1, 0, &ctx_, &conn_);
    ctx_.conn = conn_;
    p4est_partition(forest_, 1, nullptr);
    ghost_ = p4est_ghost_new(forest_, P4EST_CONNECT_FULL);
  }

  void save(const std::string& path) override {
    p4est_save_ext(path.c_str(), forest_, 1, 0);
  }

  ~Engine() override {
    if (ghost_) p4est_ghost_destroy(ghost_);
    if (forest_) p4est_destroy(forest_);
    if (conn_) p4est_connectivity_destroy(conn_);
  }
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  bool adapt(Forest& f, const std::vector<int>& marks) override {
    ctx_.replaced = 0;
    std::size_t i = 0;
    for_each_local([&](p4est_quadrant_t* q) { data_of(q)[ctx_.values] = marks.at(i++); });
    p4est_coarsen_ext(forest_, 0, 0, coarsen_marked, zero_leaf, transfer);
    p4est_refine_ext(forest_, 0, spec_.max_level, refine_marked, zero_leaf, transfer);
    p4est_balance_ext(forest_, P4EST_CONNECT_FULL, zero_leaf, transfer);
    p4est_partition(forest_, 1, nullptr);
    p4est_ghost_destroy(ghost_);
    ghost_ = p4est_ghost_new(forest_, P4EST_CONNECT_FULL);
    collect(f);
    return ctx_.replaced > 0;
  }

  void exchange(Forest& f) override {
    auto& buffer = EngineAccess::ghost_buffer(f);
    const std::size_t stride = static_cast<std::size_t>(ctx_.values) + 1;
    buffer.assign(ghost_->ghosts.elem_count * stride, 0.0);
    p4est_ghost_exchange_data(forest_, ghost_, buffer.data());
  }

  void collect(Forest& f) override {
    auto& data = EngineAccess::data(f);
    EngineAccess::ghost_buffer(f).clear();  // stale until the next exchange
    data.clear();
    for_each_local([&](p4est_quadrant_t* q) { data.push_back(data_of(q)); });
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
  template <class F>
  void for_each_local(F&& f) {
    for (p4est_topidx_t t = forest_->first_local_tree; t <= forest_->last_local_tree; ++t) {
      auto* tree = p4est_tree_array_index(forest_->trees, t);
      for (size_t i = 0; i < tree->quadrants.elem_count; ++i)
        f(p4est_quadrant_array_index(&tree->quadrants, i));
    }
  }

  ForestSpec spec_;
  BuildContext ctx_{};
  p4est_connectivity_t* conn_ = nullptr;
  p4est_t* forest_ = nullptr;
  p4est_ghost_t* ghost_ = nullptr;
};

}  // namespace

std::unique_ptr<Forest::Engine> COFLOW_FOREST_ENGINE(MPI_Comm comm, const ForestSpec& spec,
                                                     const std::string& path) {
  if (!path.empty()) return std::make_unique<Engine>(comm, spec, path);
  return std::make_unique<Engine>(comm, spec);
}

}  // namespace coflow::fluid::fv::amr
