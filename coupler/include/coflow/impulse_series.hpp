// A series of mean forces on walls (series/<file>.csv): a component hands in,
// every window, this rank's impulse on each wall slot as exact sums; the
// series adds them exactly and, at each series row, over the ranks, and
// writes the mean force since the previous row for the named slots (columns
// time, <name>_fx, _fy, _fz, in N); it keeps its exact sums in checkpoints so
// that a restart continues them bit for bit. Used for the particles' forces
// on walls (walls.csv) and the fluid's (fluid_walls.csv).
#pragma once

#include <string>
#include <vector>

#include "coflow/output.hpp"
#include "coflow/reproducible_sum.hpp"
#include "coflow/session.hpp"

namespace coflow::coupler {

class ImpulseSeries {
 public:
  // names[k] is slot slots[k] of the `slot_count` (3 values each) a window
  // hands in; w0: the window restarted from (0: none; the sums are read from
  // the checkpoint's <file>.csv otherwise, from zero with a warning where it
  // has none).
  ImpulseSeries(Session& s, const std::string& file, std::vector<std::string> names, std::vector<std::size_t> slots,
                std::size_t slot_count, long w0);
  bool empty() const { return names_.empty(); }
  // Every window: this rank's impulses of the window, N s, as exact sums,
  // added exactly to those since the last row (no message).
  void add(ExactSums window);
  // A series row at time t (collective): the mean forces since the previous
  // row, from the ranks' exact sums (the same bits for any number of ranks,
  // and whatever the windows).
  void row(double t);
  // Into this component's part of a checkpoint (collective; rank 0 writes
  // the exact sums, so that a restart continues them bit for bit).
  void save(const std::string& dir);

 private:
  void load(const std::string& path);
  Session& s_;
  std::string file_;
  std::vector<std::string> names_;
  std::vector<std::size_t> slots_;
  ExactSums sum_;       // this rank's impulse since the last row, all slots
  double since_ = 0.0;  // time of the last row
  output::Series series_;
};

}  // namespace coflow::coupler
