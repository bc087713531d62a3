// Discovery: who is in this launch. Every rank of every component says which
// component it is (and the hash of the configuration it read); the world is
// split into one communicator per component, the launch is checked against the
// configuration, and an intercommunicator is built for each connected pair
// present (fluid-immersed, immersed-particles). docs/protocol.md §1.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <map>
#include <string>

#include "coflow/run_config.hpp"

namespace coflow::coupler {

// The protocol version this process announces at discovery (protocol::kVersion).
// Only tests set another, to check that a mixed launch is refused.
void announce_protocol_version(std::uint32_t version);

// A rank that cannot start (its command line or configuration file is
// refused, e.g. a file its node cannot read) still takes part in discovery,
// announcing no configuration, so that every rank of the launch stops at
// once with exit status 2; the lowest such rank prints `problem` (tagged for
// the launcher). Collective over MPI_COMM_WORLD with the Discovery of the
// others; does not return.
[[noreturn]] void refuse_start(const std::string& component, const std::string& problem);

class Discovery {
 public:
  // Collective over MPI_COMM_WORLD; waits at most coupling.timeout. A launch
  // that does not match the configuration ends every rank with exit status 2.
  Discovery(const std::string& component, const config::Config& cfg);
  ~Discovery();
  Discovery(const Discovery&) = delete;
  Discovery& operator=(const Discovery&) = delete;

  MPI_Comm comm() const { return comm_; }
  int rank() const { return rank_; }
  int size() const { return size_; }
  int world_rank() const { return world_rank_; }
  int world_size() const { return world_size_; }
  bool standalone() const { return standalone_; }  // launched alone (component-level runs)
  bool has_partner(const std::string& component) const { return inter_.count(component) != 0; }
  MPI_Comm partner(const std::string& component) const;  // throws when not coupled to it
  int partner_ranks(const std::string& component) const;  // 0 when not in this launch

 private:
  std::string component_;
  MPI_Comm comm_ = MPI_COMM_NULL;
  int rank_ = 0, size_ = 1, world_rank_ = 0, world_size_ = 1;
  bool standalone_ = true;
  std::map<std::string, MPI_Comm> inter_;
  std::map<std::string, int> ranks_of_;  // component -> ranks in this launch
};

}  // namespace coflow::coupler
