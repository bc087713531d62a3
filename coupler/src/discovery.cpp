#include "coflow/discovery.hpp"

#include <fmt/format.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <set>
#include <stdexcept>
#include <vector>

#include "coflow/protocol.hpp"
#include "coflow/session.hpp"
#include "coflow/wait.hpp"

namespace coflow::coupler {

namespace {

// Connected pairs, in the order every component creates them.
const std::vector<std::pair<std::string, std::string>>& pairs() {
  static const std::vector<std::pair<std::string, std::string>> p{{"fluid", "immersed"},
                                                                   {"immersed", "particles"}};
  return p;
}

std::uint32_t g_protocol = protocol::kVersion;

// One rank's discovery record: which component it is, the MPI_APPNUM the
// launcher gave it, the hash of the configuration it read and the protocol
// version it was built with.
struct Hello {
  char name[16];
  int appnum;
  std::uint32_t protocol;  // where builds before version 2 left 4 bytes of padding
  std::uint64_t hash;
};
static_assert(
    sizeof(Hello) == 32 && offsetof(Hello, protocol) == 20 && offsetof(Hello, hash) == 24,
    "the discovery record's layout is part of the protocol: builds of every version must read it alike");

// The hash a rank announces: 0 says that it could not read the configuration
// (refuse_start), so a configuration whose hash is 0 announces 1.
std::uint64_t announced(std::uint64_t hash) {
  return hash == 0 ? 1 : hash;
}

// Every rank's record. Non-blocking, so that a component that never joins (an
// executable that exits at start, or hangs before MPI) ends the run after
// coupling.timeout instead of leaving the others waiting.
std::vector<Hello> gather_hellos(const std::string& component, std::uint64_t hash) {
  int world_size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &world_size);
  int* appnum_attr = nullptr;
  int flag = 0;
  MPI_Comm_get_attr(MPI_COMM_WORLD, MPI_APPNUM, &appnum_attr, &flag);
  Hello me{};
  std::snprintf(me.name, sizeof me.name, "%s", component.c_str());
  me.appnum = flag ? *appnum_attr : 0;
  me.protocol = g_protocol;
  me.hash = hash;
  std::vector<Hello> all(static_cast<std::size_t>(world_size));
  MPI_Request req = MPI_REQUEST_NULL;
  MPI_Iallgather(&me, sizeof(Hello), MPI_BYTE, all.data(), sizeof(Hello), MPI_BYTE, MPI_COMM_WORLD, &req);
  wait_one(req,
           "every component to start (discovery): one of the executables exited or hangs before joining the "
           "run; check its log and any --exe");
  return all;
}

// The lowest world rank that could not read the configuration; -1: none.
int first_refusal(const std::vector<Hello>& all) {
  for (std::size_t r = 0; r < all.size(); ++r)
    if (all[r].hash == 0) return static_cast<int>(r);
  return -1;
}

// Components built with different protocol versions: "" or the problem.
std::string check_versions(const std::string& component, const std::vector<Hello>& all) {
  for (const Hello& h : all)
    if (h.protocol != g_protocol)
      return fmt::format(
          "coflow-{} speaks coupling protocol version {} and coflow-{} version {}: build every "
          "component against the same coflow (docs/protocol.md)",
          component, g_protocol, std::string(h.name), h.protocol);
  return "";
}

// Discovery by identity: each rank says which component it is (the name is
// compiled into, or passed to, each executable) and the world is split by that
// name. MPI_APPNUM is not used to find components: under `srun --multi-prog`
// every rank has appnum 0. It still tells, where the launcher sets it, whether
// one component was launched twice. Returns the problem, or "".
std::string check_launch(const config::Config& cfg, const std::string& component, const std::vector<Hello>& all,
                         const std::map<std::string, int>& ranks_of) {
  std::map<std::string, std::set<int>> apps;  // component -> the appnums its ranks carry
  std::map<int, std::set<std::string>> names;  // appnum -> the components carrying it
  for (const Hello& h : all) {
    if (h.hash != announced(cfg.hash))
      return fmt::format("components read different configurations ({} and {}): launch every component with the "
                         "same file",
                         component, std::string(h.name));
    apps[h.name].insert(h.appnum);
    names[h.appnum].insert(h.name);
  }
  bool appnums_meaningful = true;  // false under srun --multi-prog: all ranks carry 0
  for (const auto& [app, n] : names) appnums_meaningful = appnums_meaningful && n.size() == 1;
  for (const auto& [name, a] : apps)
    if (appnums_meaningful && a.size() > 1)
      return fmt::format("component '{}' was launched twice; launch each component once", name);
  if (ranks_of.size() == 1) return "";  // standalone
  for (const auto& [name, info] : cfg.components) {
    if (!ranks_of.count(name))
      return fmt::format("the configuration has a '{}' section but coflow-{} was not launched", name, name);
    if (ranks_of.at(name) != info.ranks)
      return fmt::format("{}.ranks is {} in the configuration but {} ranks were launched", name, info.ranks,
                         ranks_of.at(name));
  }
  for (const auto& [name, n] : ranks_of)
    if (!cfg.has(name))
      return fmt::format("coflow-{} was launched but the configuration has no '{}' section", name, name);
  return "";
}

}  // namespace

void announce_protocol_version(std::uint32_t version) {
  g_protocol = version;
}

void refuse_start(const std::string& component, const std::string& problem) {
  int world_rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &world_rank);
  try {
    if (first_refusal(gather_hellos(component, 0)) == world_rank)
      std::cerr << kFailedTag << " " << component << " " << world_rank << " " << problem << std::endl;
  } catch (const TimeoutError&) {  // the others never came: say it here
    std::cerr << kFailedTag << " " << component << " " << world_rank << " " << problem << std::endl;
    // The gather is still pending: MPI_Finalize could wait for the absent
    // ranks for ever (an unfinished collective), so end the job instead.
    MPI_Abort(MPI_COMM_WORLD, 2);
  }
  MPI_Finalize();
  std::exit(2);
}

Discovery::Discovery(const std::string& component, const config::Config& cfg) : component_(component) {
  MPI_Comm_rank(MPI_COMM_WORLD, &world_rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &world_size_);
  const std::vector<Hello> all = gather_hellos(component_, announced(cfg.hash));
  // A rank that could not read the configuration has said why (refuse_start).
  if (first_refusal(all) >= 0) {
    MPI_Finalize();
    std::exit(2);
  }
  // Every rank reaches the same verdict from the same data, so all fail together.
  std::map<std::string, int> first_rank;  // component -> lowest world rank
  for (int r = 0; r < world_size_; ++r) {
    const std::string name(all[r].name);
    if (!first_rank.count(name)) first_rank[name] = r;
    ++ranks_of_[name];
  }
  int color = 0;  // the component's place among the names (the map is sorted)
  for (const auto& [name, r] : first_rank) {
    if (name == component_) break;
    ++color;
  }
  MPI_Comm_split(MPI_COMM_WORLD, color, world_rank_, &comm_);
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
  standalone_ = first_rank.size() == 1;
  // A build from before the version check does not reach this verdict and
  // would go on into MPI_Intercomm_create: the launch is aborted, not finalised.
  const std::string mixed = check_versions(component_, all);
  const std::string problem = mixed.empty() ? check_launch(cfg, component_, all, ranks_of_) : mixed;
  if (!problem.empty()) {
    if (world_rank_ == 0) std::cerr << kFailedTag << " " << component_ << " " << rank_ << " " << problem << std::endl;
    if (rank_ == 0) std::cerr << "coflow-" << component_ << ": error: " << problem << std::endl;
    if (!mixed.empty()) MPI_Abort(MPI_COMM_WORLD, 2);
    MPI_Finalize();
    std::exit(2);
  }
  int tag = 700;
  for (const auto& [a, b] : pairs()) {
    ++tag;
    if (component_ != a && component_ != b) continue;
    const std::string other = component_ == a ? b : a;
    if (!first_rank.count(other)) continue;
    MPI_Comm inter = MPI_COMM_NULL;
    MPI_Intercomm_create(comm_, 0, MPI_COMM_WORLD, first_rank[other], tag, &inter);
    inter_[other] = inter;
  }
}

Discovery::~Discovery() {
  for (auto& [name, c] : inter_) MPI_Comm_free(&c);
  if (comm_ != MPI_COMM_NULL) MPI_Comm_free(&comm_);
}

MPI_Comm Discovery::partner(const std::string& component) const {
  auto it = inter_.find(component);
  if (it == inter_.end())
    throw std::logic_error(fmt::format("{} is not coupled to {} in this launch", component_, component));
  return it->second;
}

int Discovery::partner_ranks(const std::string& component) const {
  auto it = ranks_of_.find(component);
  return it == ranks_of_.end() ? 0 : it->second;
}

}  // namespace coflow::coupler
