// The run directory: its folders, the resolved configuration, the component's
// log, the snapshot index and run.xdmf, checkpoints (written to a .partial name
// and renamed once every component has written its part) and summary.json.
// docs/protocol.md §4-5.
#pragma once

#include <mpi.h>

#include <string>
#include <vector>

#include "coflow/run_config.hpp"

namespace coflow::coupler {

// The complete checkpoints of a run directory (checkpoints/window_NNNNNN, not
// .partial), oldest first (by window number).
std::vector<std::string> complete_checkpoints(const std::string& run_dir);
// The window number of a checkpoint's directory (window_NNNNNN), -1 for any
// other name (a .partial one among them).
long checkpoint_window(const std::string& path);

class RunDirectory {
 public:
  // Collective over the component: creates the folders, writes config.yaml
  // (world rank 0) and opens the component's log.
  RunDirectory(const std::string& component, const config::Config& cfg, MPI_Comm comm, int rank, int world_rank);

  const std::string& path() const { return dir_; }
  std::string component_dir() const { return dir_ + "/" + component_; }
  // Index snapshot `number` of this component at `time` and rebuild run.xdmf
  // (component rank 0).
  void snapshot_written(long number, double time, std::size_t count, const std::vector<std::string>& fields) const;
  // This component's part of checkpoint w (collective over the component).
  std::string begin_checkpoint(long w) const;
  // Collective over all components: complete checkpoint w (time w x window),
  // keep the newest run.checkpoint.keep.
  // from_outputs: the window came from outputs_window (checkpoint.yaml says so).
  void end_checkpoint(long w, double window, bool from_outputs) const;
  // World rank 0: summary.json and the final run.xdmf.
  void write_summary(const std::string& json) const;
  // A failure's line in logs/FAILED (any rank; never throws).
  void record_failure(int rank, const std::string& reason) const noexcept;

 private:
  void write_xdmf() const;

  std::string component_;
  const config::Config& cfg_;
  MPI_Comm comm_;
  int rank_, world_rank_;
  std::string dir_;
};

}  // namespace coflow::coupler
