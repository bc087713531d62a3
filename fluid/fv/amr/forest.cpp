#include "fluid/fv/amr/forest.hpp"

#include <fmt/format.h>
#include <p4est_base.h>
#include <sc.h>

#include <cmath>
#include <mutex>
#include <stdexcept>

#include "coflow/session.hpp"

namespace coflow::fluid::fv::amr {
namespace {

// p4est's and libsc's logging to errors only, once per process (p4est and
// p8est are one package: registering it twice aborts).
void quiet_p4est_once() {
  static std::once_flag once;
  std::call_once(once, [] {
    sc_set_log_defaults(nullptr, nullptr, SC_LP_ERROR);
    p4est_init(nullptr, SC_LP_ERROR);
    // p4est aborts on a file it cannot read or write (a truncated or foreign
    // forest.p4est in a checkpoint, a full disk while saving one) after
    // printing the error: the run then stops as any failing component does,
    // with a reason (its default abort raised SIGABRT, and summary.json said
    // only that a process was signalled).
    sc_set_abort_handler([] {
      coupler::fail_running(
          "refinement: p4est stopped on the error printed above it in this component's output (while it "
          "loads or saves a checkpoint: a forest.p4est that is truncated or not this run's, or one that "
          "could "
          "not be written; restart from another checkpoint, or free space where the run writes)");
    });
  });
}

}  // namespace

Forest::Forest(MPI_Comm comm, const ForestSpec& spec) : Forest(comm, spec, std::string()) {}

Forest::Forest(MPI_Comm comm, const ForestSpec& spec, const std::string& path) : spec_(spec), comm_(comm) {
  if (spec.dims != 2 && spec.dims != 3) throw std::invalid_argument("refinement: dims must be 2 or 3");
  if (spec.dims == 2 && (spec.trees[2] != 1 || spec.periodic[2]))
    throw std::invalid_argument("refinement: a 2D brick has one tree along z and no z period");
  if (spec.patch < 4 || spec.patch % 2 != 0)
    throw std::invalid_argument("refinement: a patch needs an even number of cells, at least 4");
  if (spec.max_level < spec.min_level) throw std::invalid_argument("refinement: max_level below min_level");
  quiet_p4est_once();
  engine_ =
      spec.dims == 2 ? make_forest_engine_2d(comm, spec, path) : make_forest_engine_3d(comm, spec, path);
  engine_->collect(*this);
  if (!path.empty()) refuse_not_finite(path);
}

// A loaded forest's cell values, all finite on every rank, or every rank
// throws (a damaged checkpoint; a run would stop later, blaming its step).
void Forest::refuse_not_finite(const std::string& path) const {
  int bad = 0;
  for (std::size_t l = 0; l < leaves_.size(); ++l)
    for (double v : data(l)) bad |= std::isfinite(v) ? 0 : 1;
  MPI_Allreduce(MPI_IN_PLACE, &bad, 1, MPI_INT, MPI_MAX, comm_);
  if (bad)
    throw std::runtime_error(
        fmt::format("refinement: {} holds a cell value that is not finite: the checkpoint is "
                    "damaged; restart from another one",
                    path));
}

Forest::~Forest() = default;

}  // namespace coflow::fluid::fv::amr
