// Restarts: which checkpoint (`--restart DIR` or `--restart latest`), and a run
// directory that holds one history only: restarting from an older checkpoint
// into the same directory cuts every series, event log and snapshot index back
// to the checkpoint's time and removes the later snapshots and checkpoints.
#pragma once

#include <string>

#include "coflow/run_config.hpp"

namespace coflow::launcher {

// Resolve `restart` ("" for none, "latest", or a checkpoint directory) into an
// absolute checkpoint directory. Returns exit status 2, with a message, when
// there is none.
int resolve_restart(const config::Config& cfg, std::string& restart);

// Cut the run directory `dir` back to the time of checkpoint `restart`;
// returns a line per thing removed or cut (empty: nothing was later).
std::string rewind_run_directory(const config::Config& cfg, const std::string& dir, const std::string& restart);

}  // namespace coflow::launcher
