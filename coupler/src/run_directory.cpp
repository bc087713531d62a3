#include "coflow/run_directory.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <vector>

#include <fmt/format.h>

#include "coflow/log.hpp"
#include "coflow/output.hpp"
#include "coflow/trace.hpp"
#include "coflow/wait.hpp"

namespace coflow::coupler {

namespace fs = std::filesystem;

long checkpoint_window(const std::string& path) {
  const std::string n = fs::path(path).filename().string();
  if (n.rfind("window_", 0) != 0 || n.size() == 7) return -1;
  long w = 0;
  for (std::size_t i = 7; i < n.size(); ++i) {
    if (n[i] < '0' || n[i] > '9' || w > 100000000000L) return -1;
    w = 10 * w + (n[i] - '0');
  }
  return w;
}

std::vector<std::string> complete_checkpoints(const std::string& run_dir) {
  std::vector<std::pair<long, std::string>> found;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(run_dir + "/checkpoints", ec))
    if (const long w = checkpoint_window(e.path().string()); e.is_directory() && w >= 0)
      found.emplace_back(w, e.path().string());
  // By window number: window_1000000 comes after window_999999 (the names'
  // six digits grow to seven there, so their text order would not).
  std::sort(found.begin(), found.end());
  std::vector<std::string> all;
  for (auto& [w, path] : found) all.push_back(std::move(path));
  return all;
}

RunDirectory::RunDirectory(const std::string& component, const config::Config& cfg, MPI_Comm comm, int rank,
                           int world_rank)
    : component_(component), cfg_(cfg), comm_(comm), rank_(rank), world_rank_(world_rank), dir_(cfg.output_dir()) {
  if (rank_ == 0) {
    for (const char* sub : {"", "/series", "/logs", "/events", "/checkpoints"}) fs::create_directories(dir_ + sub);
    fs::create_directories(component_dir());
    if (world_rank_ == 0) output::atomic_write(dir_ + "/config.yaml", YAML::Dump(cfg_.resolved) + "\n");
  }
  MPI_Barrier(comm_);
  log::init(component_, rank_, dir_ + "/logs");
}

void RunDirectory::snapshot_written(long number, double time, std::size_t count,
                                    const std::vector<std::string>& fields) const {
  if (rank_ != 0) return;
  output::append_index(dir_, component_, {number, time, count}, fields);
  write_xdmf();
}

std::string RunDirectory::begin_checkpoint(long w) const {
  const std::string dir = fmt::format("{}/checkpoints/window_{:06d}.partial/{}", dir_, w, component_);
  // What an earlier, interrupted run left in this folder goes first: its
  // files would be promoted with this checkpoint (a file this run does not
  // write, e.g. k and epsilon from a run with turbulence, read back later).
  if (rank_ == 0) {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  MPI_Request r;
  MPI_Ibarrier(comm_, &r);
  wait_one(r, "the component's rank 0 to create the checkpoint's directory");
  return dir;
}

void RunDirectory::end_checkpoint(long w, double window, bool from_outputs) const {
  // Every rank of every component has written its part: then the checkpoint is complete.
  MPI_Request r;
  MPI_Ibarrier(MPI_COMM_WORLD, &r);
  wait_one(r, "the other components to finish their checkpoint");
  if (world_rank_ == 0) {
    Timer t(trace().io_s);
    const std::string base = fmt::format("{}/checkpoints/window_{:06d}", dir_, w);
    output::atomic_write(
        base + ".partial/checkpoint.yaml",
        fmt::format("name: {}\nwindow: {}\ntime: {:.17g}\nwindow_length: {:.17g}\nwindow_from_outputs: {}\n"
                    "output_every: {:.17g}\nscheme: {}\ndomain_lower: [{:.17g}, {:.17g}, {:.17g}]\n"
                    "domain_upper: [{:.17g}, {:.17g}, {:.17g}]\n",
                    cfg_.run.name, w, w * window, window, from_outputs, cfg_.run.output.every,
                    config::scheme_name(cfg_.coupling.scheme), cfg_.domain.lower[0], cfg_.domain.lower[1],
                    cfg_.domain.lower[2], cfg_.domain.upper[0], cfg_.domain.upper[1], cfg_.domain.upper[2]));
    fs::remove_all(base);
    fs::rename(base + ".partial", base);
    // Keep the newest run.checkpoint.keep checkpoints.
    const std::vector<std::string> all = complete_checkpoints(dir_);
    const std::size_t keep = static_cast<std::size_t>(cfg_.run.checkpoint.keep);
    for (std::size_t i = 0; i + keep < all.size(); ++i) fs::remove_all(all[i]);
    log::info("checkpoint written: {}", base);
  }
  MPI_Request done;
  MPI_Ibarrier(MPI_COMM_WORLD, &done);
  wait_one(done, "world rank 0 to complete the checkpoint");
}

void RunDirectory::write_xdmf() const {
  const auto& d = cfg_.domain;
  const auto h = d.spacing();
  output::write_xdmf(dir_, {{d.lower[0], d.lower[1], d.lower[2]}, {h[0], h[1], h[2]},
                            {d.cells[0], d.cells[1], d.cells[2]}});
}

// The index first: a summary says the run is complete, so it goes last.
void RunDirectory::write_summary(const std::string& json) const {
  write_xdmf();
  output::atomic_write(dir_ + "/summary.json", json);
}

void RunDirectory::record_failure(int rank, const std::string& reason) const noexcept {
  try {
    // One file per rank, written whole: the launcher gathers them into
    // logs/FAILED (appends from several hosts to one file can be lost on NFS).
    output::atomic_write(fmt::format("{}/logs/FAILED.{}.{}", dir_, component_, rank),
                         fmt::format("{} rank {}: {}\n", component_, rank, reason));
  } catch (...) {
  }
}

}  // namespace coflow::coupler
