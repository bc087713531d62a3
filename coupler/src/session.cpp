#include "coflow/session.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <set>

#include "coflow/discovery.hpp"
#include "coflow/gather.hpp"
#include "coflow/log.hpp"
#include "coflow/output.hpp"
#include "coflow/wait.hpp"

namespace coflow::coupler {

Trace& trace() {
  static Trace t;
  return t;
}

Session::Session(std::string component, config::Config cfg, Args args)
    : component_(std::move(component)), cfg_(std::move(cfg)), args_(std::move(args)) {
  start_ = now();
  set_timeout(cfg_.coupling.timeout);
  discovery_ = std::make_unique<Discovery>(component_, cfg_);
  dir_ = std::make_unique<RunDirectory>(component_, cfg_, comm(), rank(), discovery_->world_rank());
  log::info("coflow-{} started: {} rank(s), {}; output in {}", component_, size(),
            standalone() ? "standalone" : "coupled", output_dir());
  read_restart();
  clock_ = std::make_unique<Clock>(cfg_, restart_window_, restart_window_length_, args_.restart + "/checkpoint.yaml");
}

Session::~Session() = default;

void Session::read_restart() {
  if (args_.restart.empty()) return;
  const std::string file = args_.restart + "/checkpoint.yaml";
  YAML::Node c;
  try {
    c = YAML::LoadFile(file);
  } catch (const std::exception&) {
    throw std::runtime_error(fmt::format("--restart {}: no readable checkpoint.yaml (is it a directory under "
                                         "<out>/checkpoints/?)",
                                         args_.restart));
  }
  restart_window_ = c["window"].as<long>();
  restart_window_length_ = c["window_length"].as<double>();
  log::info("restarting from {} (window {}, t = {} s)", args_.restart, restart_window_, c["time"].as<double>());
}

std::string Session::restart_dir() const { return args_.restart + "/" + component_; }

void Session::checkpoint(long w, const std::function<void(const std::string&)>& save) {
  if (!checkpoint_due(w)) return;
  const std::string dir = begin_checkpoint(w);  // its barrier counts as waiting (wait_s)
  {
    Timer t(trace().io_s);
    save(dir);
  }
  end_checkpoint(w);  // its waits for the others count as waiting, once
}

Decomposition Session::decomposition_of(const std::string& component, int ranks) const {
  const auto& d = cfg_.domain;
  std::array<int, 3> dims{0, 0, 0};
  if (cfg_.has(component)) {
    const auto& info = cfg_.component(component);
    if (!info.decomposition.is_auto && info.ranks == ranks) dims = info.decomposition.value;
  }
  return Decomposition({d.cells[0], d.cells[1], d.cells[2]}, ranks, dims, d.periodic);
}

double Session::negotiate_window(double preferred) { return clock_->negotiate(preferred); }

void Session::window_done(long w) {
  if (discovery_->world_rank() != 0) return;
  const double t = now();
  if (w < windows() && t - last_progress_ < 0.25) return;
  last_progress_ = t;
  std::printf("%s %.9g %.9g %ld %ld %.3f\n", kProgressTag, w * window(), cfg_.run.end_time, w, windows(),
              t - start_);
  std::fflush(stdout);
}

std::string Session::snapshot_file(long w) const { return output::snapshot_name(clock_->snapshot_number(w)); }

void Session::snapshot_written(long w, std::size_t count, const std::vector<std::string>& fields) {
  // Every component's snapshot of window w at the same time, w x window,
  // whatever round-off its own clock has gathered (sub-steps add up), so that
  // ParaView shows fluid and particles at one time.
  dir_->snapshot_written(clock_->snapshot_number(w), static_cast<double>(w) * window(), count, fields);
}

void Session::set_final(const std::string& key, double value) {
  auto it = std::find_if(finals_.begin(), finals_.end(), [&](auto& p) { return p.first == key; });
  if (it != finals_.end())
    it->second = value;
  else
    finals_.emplace_back(key, value);
}

// This component's entry of summary.json (component rank 0; "" elsewhere):
// the maximum of each time over its ranks (compute: the busiest rank's own
// wall less its exchange, waiting and I/O, not a difference of maxima from
// different ranks), the means of exchange and waiting, the sum of bytes, the
// finals.
std::string Session::summary_entry() {
  const Trace& t = trace();
  const double wall = now() - start_;
  double times[6] = {wall, t.exchange_s, t.wait_s, t.io_s, t.halo_s, wall - t.exchange_s - t.wait_s - t.io_s},
         tmax[6], mean[2] = {t.exchange_s, t.wait_s}, msum[2];
  unsigned long long counts[4] = {t.bytes_sent, t.bytes_received, t.exchanges, t.steps}, csum[4];
  MPI_Reduce(times, tmax, 6, MPI_DOUBLE, MPI_MAX, 0, comm());
  MPI_Reduce(mean, msum, 2, MPI_DOUBLE, MPI_SUM, 0, comm());
  MPI_Reduce(counts, csum, 4, MPI_UNSIGNED_LONG_LONG, MPI_SUM, 0, comm());
  if (rank() != 0) return "";
  const int n = size();
  const double compute = std::max(0.0, tmax[5]);
  const auto& info = cfg_.has(component_) ? cfg_.component(component_) : config::ComponentInfo{};
  std::string entry = fmt::format(
      "{}: {{\"variant\": {}, \"ranks\": {}, \"steps\": {}, \"wall_s\": {:.6f}, \"compute_s\": "
      "{:.6f}, \"exchange_s\": {:.6f}, \"wait_s\": {:.6f}, \"io_s\": {:.6f}, \"halo_s\": {:.6f}, "
      "\"exchange_mean_s\": {:.6f}, \"wait_mean_s\": {:.6f}, \"bytes_sent\": {}, \"bytes_received\": {}, "
      "\"exchanges\": {}",
      output::json_quote(component_), output::json_quote(info.variant), n, csum[3] / n, tmax[0], compute,
      tmax[1], tmax[2], tmax[3], tmax[4], msum[0] / n, msum[1] / n, csum[0], csum[1], csum[2]);
  entry += ", \"final\": {";
  for (std::size_t i = 0; i < finals_.size(); ++i)
    entry += fmt::format("{}{}: {}", i ? ", " : "", output::json_quote(finals_[i].first),
                         std::isfinite(finals_[i].second) ? fmt::format("{:.17g}", finals_[i].second)
                                                          : std::string("null"));  // JSON has no NaN
  entry += "}}";
  log::info("finished: {} steps, wall {:.3f} s (compute {:.3f}, exchange {:.3f}, wait {:.3f}, io {:.3f})",
            csum[3] / n, tmax[0], compute, tmax[1], tmax[2], tmax[3]);
  return entry;
}

void Session::finish() {
  if (finished_) return;
  finished_ = true;
  const std::string entry = summary_entry();
  // Every component here before the blocking gather (wait_all: a component
  // still stepping, or one that ended without finish(), ends the run after
  // coupling.timeout instead of hanging it); kept out of the trace's wait.
  double end_wait = 0.0;
  const auto all_here = [&end_wait](const char* what) {
    MPI_Request r;
    MPI_Ibarrier(MPI_COMM_WORLD, &r);
    wait_all({&r, 1}, what, &end_wait);
  };
  all_here(
      "every component to finish: one is still stepping after coupling.timeout, or ended without finishing");
  // Gather the component entries on world rank 0.
  std::vector<int> lens, displs;
  const std::vector<char> gathered =
      gather_to_root<char>(MPI_COMM_WORLD, std::span<const char>(entry.data(), entry.size()), MPI_CHAR, &lens, &displs);
  if (discovery_->world_rank() == 0) {
    const std::string all(gathered.begin(), gathered.end());
    std::string comps;
    for (int i = 0; i < discovery_->world_size(); ++i)
      if (lens[i] > 0) comps += (comps.empty() ? "" : ",\n    ") + all.substr(displs[i], lens[i]);
    dir_->write_summary(fmt::format(
        "{{\n  \"name\": {},\n  \"status\": \"ok\",\n  \"end_time\": {:.17g},\n  \"time_reached\": {:.17g},\n"
        "  \"window\": {:.17g},\n"
        "  \"windows\": {},\n  \"restarted_from_window\": {},\n  \"windows_run\": {},\n  \"wall_s\": "
        "{:.6f},\n"
        "  \"scheme\": {},\n  \"components\": {{\n    {}\n  }}\n}}\n",
        output::json_quote(cfg_.run.name), cfg_.run.end_time, static_cast<double>(windows()) * window(),
        window(), windows(), restart_window(), windows() - restart_window(), now() - start_,
        output::json_quote(config::scheme_name(cfg_.coupling.scheme)), comps));
  }
  all_here("world rank 0 to write summary.json");
}

void Session::fail(const std::string& reason, int code) {
  const int r = discovery_ ? rank() : 0;
  log::error("{}", reason);
  std::fprintf(stderr, "%s %s %d %s\n", kFailedTag, component_.c_str(), r, reason.c_str());
  std::fflush(stderr);
  if (dir_) dir_->record_failure(r, reason);
  MPI_Abort(MPI_COMM_WORLD, code);
  std::_Exit(code);
}

// ------------------------------------------------------------ run_component --

namespace {
Session* g_running = nullptr;  // the session run_component made, while its body runs
}

void fail_running(const std::string& reason) {
  if (g_running) g_running->fail(reason + output::low_space_note(g_running->output_dir()), 1);
  int world_rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &world_rank);
  std::fprintf(stderr, "%s %s %d %s\n", kFailedTag, "unknown", world_rank, reason.c_str());
  std::fflush(stderr);
  MPI_Abort(MPI_COMM_WORLD, 1);
  std::_Exit(1);
}

int run_component(const std::string& component, int argc, char** argv,
                  const config::Catalog& catalog, const std::function<void(Session&)>& body) {
  MPI_Init(&argc, &argv);
  int world_rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &world_rank);

  Args args;
  CLI::App app{fmt::format("coflow-{}: the {} component of a coflow run", component, component)};
  app.add_option("config", args.config, "run configuration (YAML)")->required();
  app.add_option("--restart", args.restart, "checkpoint directory to restart from");
  app.add_option("--set", args.overrides, "override a key: key.path=value");
  std::string problem;  // empty: the command line and the file read well here
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) {  // --help
      app.exit(e);
      MPI_Finalize();
      return 0;
    }
    problem = fmt::format("coflow-{}: {}", component, e.what());
  }
  config::Config cfg;
  if (problem.empty()) try {
      cfg = config::parse_config(args.config, catalog, args.overrides);
      if (!cfg.has(component))
        problem = fmt::format(
            "{}: {}: the configuration has no '{}' section (or it says none), so coflow-{} has "
            "nothing to run",
            args.config, component, component, component);
    } catch (const config::ConfigError& e) {
      problem = e.what();
    }
  // Most problems are the same on every rank, but a file one rank cannot read
  // (another node's file system under srun) fails that rank alone: it still
  // takes part in discovery, so that every rank stops at once (exit status 2)
  // and the lowest failing one says why.
  if (!problem.empty()) refuse_start(component, problem);

  std::unique_ptr<Session> session;
  try {
    session = std::make_unique<Session>(component, std::move(cfg), args);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s %s %d %s\n", kFailedTag, component.c_str(), world_rank, e.what());
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  g_running = session.get();
  try {
    body(*session);
    session->finish();
  } catch (const config::ConfigError& e) {
    session->fail(e.what(), 2);
  } catch (const output::WriteError& e) {
    // HDF5's errors do not say that the disk is full: the free space of the
    // run directory's file system is added where it is low.
    session->fail(e.what() + output::low_space_note(session->output_dir()), 1);
  } catch (const std::exception& e) {
    session->fail(e.what(), 1);
  }
  g_running = nullptr;
  session.reset();
  MPI_Finalize();
  return 0;
}

int run_component(const std::string& component, int argc, char** argv, const std::function<void(Session&)>& body) {
  static const config::Catalog open = config::open_catalog();
  return run_component(component, argc, argv, open, body);
}

}  // namespace coflow::coupler
