// The run's clock: the coupling window every component agreed on, how many
// windows cover run.end_time, and which windows carry a snapshot, a series row
// or a checkpoint. docs/protocol.md §2.
#pragma once

#include <cmath>
#include <string>

#include "coflow/run_config.hpp"

namespace coflow::coupler {

// The window for a natural step (the smallest component step, e.g. the
// fluid's): coupling.window when given; else the step shortened so that a
// whole number of windows makes run.output.every, snapshots then falling at
// their exact times (as OpenFOAM's adjustableRunTime adjusts its time step),
// when that costs at most 10 % of the step; else the step itself (snapshots
// at the first window end past each multiple, at most one window late). A
// step that already makes `every` in a whole number, to 1e-6, is kept.
double output_window(double step, const config::Config& cfg);

// The window when no component has a natural step: one per output interval,
// or the largest part of it (up to a thousandth) that also ends the run at
// run.end_time; where none does, the whole number of windows that ends at
// run.end_time. It depends on run.end_time: the launcher refuses a restart
// whose end time would change it (checkpoint.yaml's window_from_outputs).
double outputs_window(const config::Config& cfg);

// The whole intervals a time x (in intervals) has reached: a window end
// within 1e-6 of an interval short of a multiple reaches it (output_window
// keeps a step that makes the interval in a whole number to 1e-6).
inline constexpr double kReach = 1e-6;
inline double multiples_reached(double x) {
  return std::floor(x + kReach);
}

// The most windows a run may have: their count and each window's number
// stay exact in a double and far inside a long.
inline constexpr double kMostWindows = 1e15;

class Clock {
 public:
  // restart_window, restart_window_length: of the checkpoint restarted from (0: none).
  Clock(const config::Config& cfg, long restart_window, double restart_window_length, std::string restart_file);

  // Collective over every component: each offers its preferred window (the
  // fluid its step; 0 for no preference). The result is coupling.window when
  // given, else output_window() of the smallest offer (the fluid then takes
  // it as its step); with no offer, one window per output interval.
  double negotiate(double preferred);
  double window() const { return window_; }
  long windows() const { return windows_; }
  // Sub-steps of a solver with natural step `step` inside one window.
  long substeps(double step) const;
  // Whether a snapshot / series row / checkpoint falls at the end of window w
  // (1-based; window 0 is the initial state).
  bool snapshot_due(long w) const;
  // The number of the snapshot written at window w: the multiple of
  // run.output.every it reaches (the final window's, when it reaches none, the
  // one after), so that snapshot k is at time k x every in every run, whatever
  // the window.
  long snapshot_number(long w) const;
  bool series_due(long w) const;
  bool checkpoint_due(long w) const;
  long restart_window() const { return restart_window_; }
  // Whether the window came from outputs_window (no natural step, none given).
  bool window_from_outputs() const { return from_outputs_; }

 private:
  const config::Config& cfg_;
  long restart_window_ = 0;
  double restart_window_length_ = 0.0;
  std::string restart_file_;
  double window_ = 0.0;
  long windows_ = 0;
  bool from_outputs_ = false;
};

}  // namespace coflow::coupler
