#include "coflow/session.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <limits>
#include <set>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "coflow/gather.hpp"
#include "coflow/log.hpp"
#include "coflow/output.hpp"
#include "coflow/wait.hpp"

namespace coflow::coupler {

namespace fs = std::filesystem;

Trace& trace() {
  static Trace t;
  return t;
}

namespace {


// Connected pairs, in the order every component creates them.
const std::vector<std::pair<std::string, std::string>>& pairs() {
  static const std::vector<std::pair<std::string, std::string>> p{{"fluid", "immersed"},
                                                                   {"immersed", "particles"}};
  return p;
}

}  // namespace

Session::Session(std::string component, config::Config cfg, Args args)
    : component_(std::move(component)), cfg_(std::move(cfg)), args_(std::move(args)) {
  start_ = now();
  MPI_Comm_rank(MPI_COMM_WORLD, &world_rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &world_size_);
  set_timeout(cfg_.coupling.timeout);
  discover();
  prepare_output();
  if (!args_.restart.empty()) {
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
}

std::string Session::restart_dir() const { return args_.restart + "/" + component_; }

bool Session::checkpoint_due(long w) const {
  const auto& c = cfg_.run.checkpoint;
  if (c.every <= 0 || w <= 0 || w == restart_window_) return false;
  const double a = (w - 1) * window_ / c.every, b = w * window_ / c.every;
  return std::floor(b + 1e-9) > std::floor(a + 1e-9);
}

void Session::checkpoint(long w, const std::function<void(const std::string&)>& save) {
  if (!checkpoint_due(w)) return;
  Timer t(trace().io_s);
  save(begin_checkpoint(w));
  end_checkpoint(w);
}

std::string Session::begin_checkpoint(long w) {
  const std::string dir = fmt::format("{}/checkpoints/window_{:06d}.partial/{}", dir_, w, component_);
  if (rank_ == 0) fs::create_directories(dir);
  MPI_Barrier(comm_);
  return dir;
}

void Session::end_checkpoint(long w) {
  // Every rank of every component has written its part: then the checkpoint is complete.
  MPI_Request r;
  MPI_Ibarrier(MPI_COMM_WORLD, &r);
  wait_one(r, "the other components to finish their checkpoint");
  if (world_rank_ == 0) {
    const std::string base = fmt::format("{}/checkpoints/window_{:06d}", dir_, w);
    output::atomic_write(base + ".partial/checkpoint.yaml",
                         fmt::format("name: {}\nwindow: {}\ntime: {:.17g}\nwindow_length: {:.17g}\n", cfg_.run.name, w,
                                     w * window_, window_));
    fs::remove_all(base);
    fs::rename(base + ".partial", base);
    // Keep the newest run.checkpoint.keep checkpoints.
    std::vector<std::string> all;
    for (const auto& e : fs::directory_iterator(dir_ + "/checkpoints")) {
      const std::string n = e.path().filename().string();
      if (e.is_directory() && n.rfind("window_", 0) == 0 && n.find(".partial") == std::string::npos)
        all.push_back(e.path().string());
    }
    std::sort(all.begin(), all.end());
    const std::size_t keep = static_cast<std::size_t>(cfg_.run.checkpoint.keep);
    for (std::size_t i = 0; i + keep < all.size(); ++i) fs::remove_all(all[i]);
    log::info("checkpoint written: {}", base);
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

Session::~Session() {
  for (auto& [name, c] : inter_) MPI_Comm_free(&c);
  if (comm_ != MPI_COMM_NULL) MPI_Comm_free(&comm_);
}

namespace {

// One rank's discovery record: which component it is, the MPI_APPNUM the
// launcher gave it, and the hash of the configuration it read.
struct Hello {
  char name[16];
  int appnum;
  std::uint64_t hash;
};

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
    if (h.hash != cfg.hash)
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

void Session::discover() {
  int* appnum_attr = nullptr;
  int flag = 0;
  MPI_Comm_get_attr(MPI_COMM_WORLD, MPI_APPNUM, &appnum_attr, &flag);
  Hello me{};
  std::snprintf(me.name, sizeof me.name, "%s", component_.c_str());
  me.appnum = flag ? *appnum_attr : 0;
  me.hash = cfg_.hash;
  std::vector<Hello> all(world_size_);
  // Non-blocking, so that a component that never joins (an executable that
  // exits at start, or hangs before MPI) ends the run after coupling.timeout
  // instead of leaving the others waiting.
  MPI_Request req = MPI_REQUEST_NULL;
  MPI_Iallgather(&me, sizeof(Hello), MPI_BYTE, all.data(), sizeof(Hello), MPI_BYTE, MPI_COMM_WORLD, &req);
  wait_one(req, "every component to start (discovery): one of the executables exited or hangs before joining the "
                "run; check its log and any --exe");
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
  const std::string problem = check_launch(cfg_, component_, all, ranks_of_);
  if (!problem.empty()) {
    if (world_rank_ == 0) std::cerr << kFailedTag << " " << component_ << " " << rank_ << " " << problem << std::endl;
    if (rank_ == 0) std::cerr << "coflow-" << component_ << ": error: " << problem << std::endl;
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

MPI_Comm Session::partner(const std::string& component) const {
  auto it = inter_.find(component);
  if (it == inter_.end())
    throw std::logic_error(fmt::format("{} is not coupled to {} in this launch", component_, component));
  return it->second;
}

int Session::partner_ranks(const std::string& component) const {
  auto it = ranks_of_.find(component);
  return it == ranks_of_.end() ? 0 : it->second;
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

void Session::prepare_output() {
  dir_ = cfg_.output_dir();
  if (rank_ == 0) {
    for (const char* sub : {"", "/series", "/logs", "/events", "/checkpoints"}) fs::create_directories(dir_ + sub);
    fs::create_directories(component_dir());
    if (world_rank_ == 0) output::atomic_write(dir_ + "/config.yaml", YAML::Dump(cfg_.resolved) + "\n");
  }
  MPI_Barrier(comm_);
  log::init(component_, rank_, dir_ + "/logs/" + component_ + ".log");
  log::info("coflow-{} started: {} rank(s), {}; output in {}", component_, size_,
            standalone_ ? "standalone" : "coupled", dir_);
}

double Session::negotiate_window(double preferred) {
  const double offer = preferred > 0 ? preferred : std::numeric_limits<double>::infinity();
  double w = offer;
  MPI_Allreduce(&offer, &w, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
  if (!cfg_.coupling.window.is_auto) w = cfg_.coupling.window.value;
  if (!std::isfinite(w)) {
    // Nobody has a natural step: one window per output interval.
    const auto& o = cfg_.run.output;
    const double series = o.series_every.is_auto ? o.every : o.series_every.value;
    w = cfg_.run.end_time;
    for (double e : {o.every, series})
      if (e > 0) w = std::min(w, e);
  }
  window_ = w;
  windows_ = std::max(1L, static_cast<long>(std::ceil(cfg_.run.end_time / w - 1e-9)));
  if (restart_window_ > 0 && std::abs(window_ - restart_window_length_) > 1e-12 * window_)
    throw config::ConfigError({config::Problem{
        args_.restart + "/checkpoint.yaml", 0, 0, "window_length",
        fmt::format("the checkpoint was written with windows of {:.17g} s but this run has {:.17g} s: restart "
                    "with the configuration of the run that wrote it",
                    restart_window_length_, window_)}});
  log::info("coupling window {:.6g} s, {} windows to t = {:.6g} s ({})", window_, windows_,
            cfg_.run.end_time, config::scheme_name(cfg_.coupling.scheme));
  return window_;
}

long Session::substeps(double step) const {
  if (step <= 0) return 1;
  return std::max(1L, static_cast<long>(std::ceil(window_ / step - 1e-9)));
}

static bool crosses(long w, double window, double every) {
  if (every <= 0) return false;
  if (w == 0) return true;
  const double a = (w - 1) * window / every, b = w * window / every;
  return std::floor(b + 1e-9) > std::floor(a + 1e-9);
}

bool Session::snapshot_due(long w) const {
  if (w == restart_window_ && w > 0) return false;  // the run being restarted wrote it
  return crosses(w, window_, cfg_.run.output.every) || (w == windows_ && cfg_.run.output.every > 0);
}

bool Session::series_due(long w) const {
  if (w == restart_window_ && w > 0) return false;
  const auto& o = cfg_.run.output;
  const double every = o.series_every.is_auto ? o.every : o.series_every.value;
  if (every <= 0) return w == 0 || w == windows_;
  return crosses(w, window_, every) || w == windows_;
}

void Session::window_done(long w) {
  if (world_rank_ != 0) return;
  const double t = now();
  if (w < windows_ && t - last_progress_ < 0.25) return;
  last_progress_ = t;
  std::printf("%s %.9g %.9g %ld %ld %.3f\n", kProgressTag, w * window_, cfg_.run.end_time, w, windows_,
              t - start_);
  std::fflush(stdout);
}

void Session::snapshot_written(long step, double time, std::size_t count,
                               const std::vector<std::string>& fields) {
  if (rank_ != 0) return;
  // Index every component's snapshot of window w at the same time, w x window,
  // whatever round-off its own clock has gathered (sub-steps add up), so that
  // ParaView shows fluid and particles at one time.
  if (window_ > 0) time = static_cast<double>(step) * window_;
  output::append_index(dir_, component_, {step, time, count}, fields);
  const auto& d = cfg_.domain;
  const auto h = d.spacing();
  output::write_xdmf(dir_, {{d.lower[0], d.lower[1], d.lower[2]}, {h[0], h[1], h[2]},
                            {d.cells[0], d.cells[1], d.cells[2]}});
}

void Session::set_final(const std::string& key, double value) {
  auto it = std::find_if(finals_.begin(), finals_.end(), [&](auto& p) { return p.first == key; });
  if (it != finals_.end())
    it->second = value;
  else
    finals_.emplace_back(key, value);
}

void Session::finish() {
  if (finished_) return;
  finished_ = true;
  // Per component: the maximum of each time over its ranks, the sum of bytes.
  const Trace& t = trace();
  const double wall = now() - start_;
  double times[5] = {wall, t.exchange_s, t.wait_s, t.io_s, t.halo_s}, tmax[5];
  unsigned long long counts[4] = {t.bytes_sent, t.bytes_received, t.exchanges, t.steps}, csum[4];
  MPI_Reduce(times, tmax, 5, MPI_DOUBLE, MPI_MAX, 0, comm_);
  MPI_Reduce(counts, csum, 4, MPI_UNSIGNED_LONG_LONG, MPI_SUM, 0, comm_);
  std::string entry;
  if (rank_ == 0) {
    const double compute = std::max(0.0, tmax[0] - tmax[1] - tmax[2] - tmax[3]);
    const auto& info = cfg_.has(component_) ? cfg_.component(component_) : config::ComponentInfo{};
    entry = fmt::format(
        "{}: {{\"variant\": {}, \"ranks\": {}, \"steps\": {}, \"wall_s\": {:.6f}, \"compute_s\": "
        "{:.6f}, \"exchange_s\": {:.6f}, \"wait_s\": {:.6f}, \"io_s\": {:.6f}, \"halo_s\": {:.6f}, "
        "\"bytes_sent\": {}, \"bytes_received\": {}, \"exchanges\": {}",
        output::json_quote(component_), output::json_quote(info.variant), size_, csum[3] / size_,
        tmax[0], compute, tmax[1], tmax[2], tmax[3], tmax[4], csum[0], csum[1], csum[2]);
    entry += ", \"final\": {";
    for (std::size_t i = 0; i < finals_.size(); ++i)
      entry += fmt::format("{}{}: {:.17g}", i ? ", " : "", output::json_quote(finals_[i].first), finals_[i].second);
    entry += "}}";
    log::info("finished: {} steps, wall {:.3f} s (compute {:.3f}, exchange {:.3f}, wait {:.3f}, io {:.3f})",
              csum[3] / size_, tmax[0], compute, tmax[1], tmax[2], tmax[3]);
  }
  // Gather the component entries on world rank 0.
  std::vector<int> lens, displs;
  const std::vector<char> gathered =
      gather_to_root<char>(MPI_COMM_WORLD, std::span<const char>(entry.data(), entry.size()), MPI_CHAR, &lens, &displs);
  if (world_rank_ == 0) {
    const std::string all(gathered.begin(), gathered.end());
    std::string comps;
    for (int i = 0; i < world_size_; ++i)
      if (lens[i] > 0) comps += (comps.empty() ? "" : ",\n    ") + all.substr(displs[i], lens[i]);
    const std::string json = fmt::format(
        "{{\n  \"name\": {},\n  \"status\": \"ok\",\n  \"end_time\": {:.17g},\n  \"window\": {:.17g},\n"
        "  \"windows\": {},\n  \"wall_s\": {:.6f},\n  \"scheme\": {},\n  \"components\": {{\n    {}\n  }}\n}}\n",
        output::json_quote(cfg_.run.name), cfg_.run.end_time, window_, windows_, now() - start_,
        output::json_quote(config::scheme_name(cfg_.coupling.scheme)), comps);
    output::atomic_write(dir_ + "/summary.json", json);
    const auto& d = cfg_.domain;
    const auto h = d.spacing();
    output::write_xdmf(dir_, {{d.lower[0], d.lower[1], d.lower[2]}, {h[0], h[1], h[2]},
                              {d.cells[0], d.cells[1], d.cells[2]}});
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

void Session::fail(const std::string& reason, int code) {
  log::error("{}", reason);
  std::fprintf(stderr, "%s %s %d %s\n", kFailedTag, component_.c_str(), rank_, reason.c_str());
  std::fflush(stderr);
  try {
    std::ofstream(dir_ + "/logs/FAILED", std::ios::app) << component_ << " rank " << rank_ << ": " << reason << "\n";
  } catch (...) {
  }
  MPI_Abort(MPI_COMM_WORLD, code);
  std::_Exit(code);
}

// ------------------------------------------------------------ run_component --

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
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    MPI_Finalize();
    return rc == 0 ? 0 : 2;
  }

  config::Config cfg;
  try {
    cfg = config::parse_config(args.config, catalog, args.overrides);
    if (!cfg.has(component)) {
      if (world_rank == 0)
        std::cerr << args.config << ": " << component << ": the configuration has no '" << component
                  << "' section (or it says none), so coflow-" << component << " has nothing to run\n";
      MPI_Finalize();
      return 2;
    }
  } catch (const config::ConfigError& e) {
    // Every rank of every component reads the same file and fails the same way.
    if (world_rank == 0) std::cerr << e.what() << std::endl;
    MPI_Finalize();
    return 2;
  }

  std::unique_ptr<Session> session;
  try {
    session = std::make_unique<Session>(component, std::move(cfg), args);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s %s %d %s\n", kFailedTag, component.c_str(), world_rank, e.what());
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  try {
    body(*session);
    session->finish();
  } catch (const config::ConfigError& e) {
    session->fail(e.what(), 2);
  } catch (const std::exception& e) {
    session->fail(e.what(), 1);
  }
  session.reset();
  MPI_Finalize();
  return 0;
}

int run_component(const std::string& component, int argc, char** argv, const std::function<void(Session&)>& body) {
  static const config::Catalog open = config::open_catalog();
  return run_component(component, argc, argv, open, body);
}

}  // namespace coflow::coupler
