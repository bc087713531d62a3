// A component's view of a coupled run, in three parts: discovery (its
// communicator and the intercommunicators to its partners, coflow/discovery.hpp),
// the clock (the time windows, coflow/clock.hpp) and the run directory (output,
// checkpoints, summary, coflow/run_directory.hpp); the session adds restart,
// failure handling and the end-of-run summary. See docs/protocol.md for the
// calling sequence.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "coflow/clock.hpp"
#include "coflow/decomposition.hpp"
#include "coflow/discovery.hpp"
#include "coflow/run_config.hpp"
#include "coflow/run_directory.hpp"
#include "coflow/trace.hpp"

namespace coflow::coupler {

// Thrown by a solver for a physical failure (NaN, Mach limit): aborts the run.
class SolverError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Args {
  std::string config;
  std::string restart;  // checkpoint directory, or empty
  std::vector<std::string> overrides;
};

class Session {
 public:
  // After MPI_Init: discovery, checks, intercommunicators, run directory, logs.
  Session(std::string component, config::Config cfg, Args args);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  const std::string& component() const { return component_; }
  const config::Config& config() const { return cfg_; }
  const Args& args() const { return args_; }
  MPI_Comm comm() const { return discovery_->comm(); }
  int rank() const { return discovery_->rank(); }
  int size() const { return discovery_->size(); }
  // True when this component was launched alone (component-level runs).
  bool standalone() const { return discovery_->standalone(); }

  // Partners present in this launch, and the intercommunicator to each.
  bool has_partner(const std::string& component) const { return discovery_->has_partner(component); }
  MPI_Comm partner(const std::string& component) const { return discovery_->partner(component); }

  // This component's decomposition of the fluid grid, and any other's.
  Decomposition decomposition() const { return decomposition_of(component_, size()); }
  Decomposition decomposition_of(const std::string& component, int ranks) const;
  int partner_ranks(const std::string& component) const { return discovery_->partner_ranks(component); }

  // --- time windows -------------------------------------------------------
  // Collective over every component: each offers its preferred window (the
  // fluid its step; 0 for no preference). The result is coupling.window when
  // given, else the smallest offer. Sets the number of windows to cover end_time.
  double negotiate_window(double preferred);
  double window() const { return clock_->window(); }
  // Sub-steps of a solver with natural step `step` inside one window (the last
  // sub-step is shortened so the window is covered exactly).
  long substeps(double step) const { return clock_->substeps(step); }
  long windows() const { return clock_->windows(); }
  // Whether a snapshot / series row falls at the end of window w (1-based);
  // window 0 is the initial state.
  bool snapshot_due(long w) const { return clock_->snapshot_due(w); }
  bool series_due(long w) const { return clock_->series_due(w); }
  // Progress for the launcher (world rank 0 reports, throttled).
  void window_done(long w);

  // --- output ---------------------------------------------------------------
  const std::string& output_dir() const { return dir_->path(); }
  std::string component_dir() const { return dir_->component_dir(); }
  // The file name of the snapshot of window w (step_NNNNNN.h5, NNNNNN its number).
  std::string snapshot_file(long w) const;
  // Record the snapshot of window w in the component's index and rebuild
  // run.xdmf; it is indexed at w x window (one time for all components).
  void snapshot_written(long w, std::size_t count, const std::vector<std::string>& fields);
  // Final scalars reported in summary.json (component rank 0 only).
  void set_final(const std::string& key, double value);

  // --- checkpoints -----------------------------------------------------------
  // Every component writes its state at the same windows (run.checkpoint.every):
  //   dir = s.begin_checkpoint(w);  solver.save(dir ...);  s.end_checkpoint(w);
  // The checkpoint is written into <out>/checkpoints/window_<w>.partial and renamed
  // into place once every component has finished (a collective over all), so a
  // crash never leaves a half-written checkpoint as the latest one.
  bool checkpoint_due(long w) const { return clock_->checkpoint_due(w); }
  // All of it in one call: when due, save(dir) between begin and end (I/O time).
  void checkpoint(long w, const std::function<void(const std::string&)>& save);
  std::string begin_checkpoint(long w) { return dir_->begin_checkpoint(w); }  // this component's directory in it
  void end_checkpoint(long w) { dir_->end_checkpoint(w, window(), clock_->window_from_outputs()); }
  // Restart: the window the checkpoint was written at (0 when not restarting),
  // and this component's directory in it.
  long restart_window() const { return restart_window_; }
  std::string restart_dir() const;

  // --- end -------------------------------------------------------------------
  // Collective over every component: gathers traces, writes summary.json.
  void finish();
  // Log, tell the launcher, abort the whole run. Never returns.
  [[noreturn]] void fail(const std::string& reason, int code = 1);

 private:
  void read_restart();
  std::string summary_entry();

  std::string component_;
  config::Config cfg_;
  Args args_;
  double start_ = 0.0;
  long restart_window_ = 0;
  double restart_window_length_ = 0.0;
  std::unique_ptr<Discovery> discovery_;
  std::unique_ptr<RunDirectory> dir_;
  std::unique_ptr<Clock> clock_;
  double last_progress_ = 0.0;
  std::vector<std::pair<std::string, double>> finals_;
  bool finished_ = false;
};

// Everything a component's main() does around its solver: MPI start, command
// line, strict config (exit 2 on a bad file, before any intercommunicator),
// the session, and turning any exception into a whole-run abort.
int run_component(const std::string& component, int argc, char** argv,
                  const config::Catalog& catalog, const std::function<void(Session&)>& body);
// The same for a component built outside the tree: it reads the file with
// config::open_catalog() and links libcoflow alone.
int run_component(const std::string& component, int argc, char** argv, const std::function<void(Session&)>& body);

// Fail the running component from code that cannot throw (a C library's
// abort handler, e.g. libsc's under p4est): as Session::fail on the session
// run_component made, with the low-space note of its output directory; before
// or without one, the failure line and MPI_Abort. Never returns.
[[noreturn]] void fail_running(const std::string& reason);

// Format of the lines the launcher reads from the components' output.
inline constexpr const char* kProgressTag = "@coflow progress";
inline constexpr const char* kFailedTag = "@coflow failed";

}  // namespace coflow::coupler
