#include "restart.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <sstream>
#include <vector>

#include "coflow/clock.hpp"
#include "coflow/output.hpp"
#include "coflow/run_directory.hpp"

namespace coflow::launcher {

namespace fs = std::filesystem;

namespace {

// Keep the header, a units line and the rows whose first column passes `keep`; returns
// how many rows went. A last row without its newline was cut short (a full
// disk, a killed run: a row is written with its newline in one piece) and
// goes too: the restarted run's rows would be appended to it.
template <class Keep>
long cut_csv(const fs::path& path, Keep keep) {
  std::ifstream in(path);
  const std::string all{std::istreambuf_iterator<char>(in), {}};
  in.close();
  std::istringstream lines(all);
  std::string line, text;
  long cut = 0;
  if (std::getline(lines, line)) text = line + "\n";
  while (std::getline(lines, line)) {
    if (line.empty()) continue;
    const bool torn = lines.eof() && !all.ends_with('\n');
    if (!torn && (line.starts_with("#") || keep(std::strtod(line.c_str(), nullptr))))  // a units line stays
      text += line + "\n";
    else
      ++cut;
  }
  if (cut > 0 || !all.ends_with('\n'))
    output::atomic_write(path.string(), text);  // a torn header gets its newline
  return cut;
}

// The event logs' sizes (bytes) at the checkpoint, as the particles wrote
// them (events.txt: "name bytes" lines); empty for a checkpoint from before
// they were kept.
std::map<std::string, std::uintmax_t> event_sizes(const std::string& restart) {
  std::map<std::string, std::uintmax_t> sizes;
  std::ifstream in(restart + "/particles/events.txt");
  std::string name;
  std::uintmax_t bytes = 0;
  while (in >> name >> bytes) sizes[name] = bytes;
  return sizes;
}

// An event log back to its size at the checkpoint: exactly the events written
// up to it, whatever their times (dpm stamps an event within its step, dem
// with the step's start, so a time rule is off by an event at the seam).
// Returns the rows removed.
long cut_to_size(const fs::path& path, std::uintmax_t bytes) {
  std::error_code ec;
  const std::uintmax_t now = fs::file_size(path, ec);
  if (ec || now <= bytes) return 0;
  std::ifstream in(path, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(bytes));
  const long rows = std::count(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>(), '\n');
  in.close();
  fs::resize_file(path, bytes);
  return rows;
}

// Keep the header and the index rows of the snapshots numbered up to `last`.
void cut_index(const fs::path& path, long last) {
  std::ifstream in(path);
  std::string line, text;
  bool cut = false;
  if (std::getline(in, line)) text = line + "\n";
  while (std::getline(in, line)) {
    if (line.empty() || line.find(',') == std::string::npos) continue;
    if (std::strtol(line.c_str(), nullptr, 10) <= last)
      text += line + "\n";
    else
      cut = true;
  }
  in.close();
  if (cut) output::atomic_write(path.string(), text);
}

// The snapshots of `index` the restarted run keeps: those at or before the
// checkpoint's time t, less the run's final snapshot when it fell between two
// multiples of run.output.every (it takes the next multiple's number, k + 1)
// and the restarted run goes on past t: that run writes snapshot k + 1 at its
// proper time, as a run straight to the new end does.
struct KeptSnapshots {
  long last = -1;              // the number of the last one kept
  bool dropped_final = false;  // the run's final, off-multiple snapshot goes
};

KeptSnapshots kept_snapshots(const config::Config& cfg, const fs::path& index, double t, double tol) {
  long last = -1;
  double last_time = 0.0;
  for (const output::SnapshotInfo& s : output::read_index(index.string()).rows)
    if (s.time <= t + tol && s.number > last) last = s.number, last_time = s.time;
  const double every = cfg.run.output.every;
  // Its time reaches a lower multiple than its number (the clock's own test:
  // a step a little short of dividing `every` puts snapshot k a little before
  // k x every, and it stays).
  const bool off_multiple =
      every > 0 && last > 0 && coupler::multiples_reached(last_time / every) < static_cast<double>(last);
  const bool dropped = off_multiple && cfg.run.end_time > t + tol;
  return {dropped ? last - 1 : last, dropped};
}

}  // namespace

// What the restarted run must share with the checkpoint's, checked before
// rewind_run_directory cuts anything: an end not before the checkpoint (at
// it: a finished run's last checkpoint, a restart that runs nothing), the
// same snapshot interval (snapshots are numbered by it: another one would
// number the new ones anew over the old files), and the same window where
// the file gives one (an automatic window is checked by the components'
// clock).
static std::string restart_mismatch(const config::Config& cfg, const YAML::Node& c) {
  if (!c["time"]) return {};  // no time (a hand-made file): the components check their parts
  const double t = c["time"].as<double>(), tol = 1e-9 * std::max(1.0, std::abs(t));
  if (!(cfg.run.end_time >= t - tol))
    return fmt::format(
        "run.end_time = {:.6g} s is before the checkpoint's time, {:.6g} s: the restarted run would run no "
        "window and its summary would end before its series; set run.end_time to {:.6g} s or later",
        cfg.run.end_time, t, t);
  if (const auto every = c["output_every"]; every && std::abs(every.as<double>() - cfg.run.output.every) >
                                                         1e-12 * std::max(1.0, every.as<double>()))
    return fmt::format(
        "run.output.every = {:.6g} s, but the checkpoint's run wrote snapshots every {:.6g} s: snapshots are "
        "numbered by it, and the restarted run would write new ones over the old; restart with "
        "run.output.every: {:.17g}",
        cfg.run.output.every, every.as<double>(), every.as<double>());
  if (const auto length = c["window_length"];
      length && !cfg.coupling.window.is_auto &&
      std::abs(cfg.coupling.window.value - length.as<double>()) > 1e-12 * length.as<double>())
    return fmt::format(
        "coupling.window = {:.17g} s, but the checkpoint was written with windows of {:.17g} s: restart with "
        "the window of the run that wrote it",
        cfg.coupling.window.value, length.as<double>());
  // The box and the scheme (checkpoints since 2026-12-07 say them): fields
  // and particles would load onto another box (and run.xdmf place the earlier
  // snapshots in it), and parallel-explicit's loads in flight would be dropped
  // by serial-explicit.
  if (const auto lo = c["domain_lower"], hi = c["domain_upper"]; lo && hi) {
    const auto& d = cfg.domain;
    for (int a = 0; a < 3; ++a)
      for (const auto& [now, then] :
           {std::pair{d.lower[a], lo[a].as<double>()}, std::pair{d.upper[a], hi[a].as<double>()}})
        if (std::abs(now - then) > 1e-12 * std::max({1.0, std::abs(now), std::abs(then)}))
          return fmt::format(
              "domain.lower = [{}, {}, {}] and domain.upper = [{}, {}, {}], but the checkpoint's run had "
              "[{}, {}, "
              "{}] to [{}, {}, {}]: its fields and particles would load onto another box; restart with the "
              "domain of the run that wrote it",
              d.lower[0], d.lower[1], d.lower[2], d.upper[0], d.upper[1], d.upper[2], lo[0].as<double>(),
              lo[1].as<double>(), lo[2].as<double>(), hi[0].as<double>(), hi[1].as<double>(),
              hi[2].as<double>());
  }
  if (const auto scheme = c["scheme"];
      scheme && scheme.as<std::string>() != config::scheme_name(cfg.coupling.scheme))
    return fmt::format(
        "coupling.scheme = {}, but the checkpoint was written by a {} run, whose state (the loads in flight "
        "of "
        "parallel-explicit) the other does not take up; restart with coupling.scheme: {}",
        config::scheme_name(cfg.coupling.scheme), scheme.as<std::string>(), scheme.as<std::string>());
  // No component had a natural step: the window came from the outputs and
  // the end time, and a new end time may change it, which the components'
  // clocks would refuse only after the rewind had cut the directory.
  if (const auto length = c["window_length"]; length && c["window_from_outputs"] &&
                                              c["window_from_outputs"].as<bool>() &&
                                              cfg.coupling.window.is_auto) {
    const double old = length.as<double>(), now = coupler::outputs_window(cfg);
    if (std::abs(now - old) > 1e-12 * old)
      return fmt::format(
          "the checkpoint's run took windows of {} s from its outputs and end time (no component has a "
          "natural step), and this run's (run.end_time = {} s, run.output.every and series_every) give "
          "windows of {} s; restart with --set "
          "coupling.window={} and a run.end_time that is a whole number of them (e.g. {:.12g})",
          old, cfg.run.end_time, now, old, std::ceil(cfg.run.end_time / old - 1e-9) * old);
  }
  return {};
}

static int check_restart(const config::Config& cfg, const std::string& restart) {
  std::string wrong;
  try {
    wrong = restart_mismatch(cfg, YAML::LoadFile(restart + "/checkpoint.yaml"));
  } catch (const YAML::Exception& e) {
    wrong = fmt::format("its checkpoint.yaml cannot be read ({}): restart from a checkpoint coflow wrote",
                        e.what());
  }
  if (wrong.empty()) return 0;
  std::cerr << "--restart " << restart << ": " << wrong << " (nothing in " << cfg.output_dir()
            << " was changed)\n";
  return 2;
}

int resolve_restart(const config::Config& cfg, std::string& restart) {
  if (restart.empty()) return 0;
  if (restart == "latest") {
    const auto all = coupler::complete_checkpoints(cfg.output_dir());
    if (all.empty()) {
      std::cerr << "--restart latest: no complete checkpoint in " << cfg.output_dir()
                << "/checkpoints (set run.checkpoint.every to write them)\n";
      return 2;
    }
    restart = all.back();
  }
  if (fs::path(restart).lexically_normal().filename().extension() == ".partial" ||
      fs::path(restart).lexically_normal().parent_path().extension() == ".partial") {
    std::cerr << "--restart " << restart << ": an unfinished checkpoint (a run stopped while writing it); "
              << "restart from a complete one, window_NNNNNN without .partial, or say latest\n";
    return 2;
  }
  if (!fs::is_regular_file(fs::path(restart) / "checkpoint.yaml")) {
    std::cerr << "--restart " << restart << ": not a checkpoint (no checkpoint.yaml); checkpoints are the "
              << "directories out/<name>/checkpoints/window_NNNNNN written with run.checkpoint.every, or say latest\n";
    return 2;
  }
  restart = fs::absolute(restart).lexically_normal().string();
  return check_restart(cfg, restart);
}

std::string rewind_run_directory(const config::Config& cfg, const std::string& dir, const std::string& restart) {
  const YAML::Node c = YAML::LoadFile(restart + "/checkpoint.yaml");
  const long w = c["window"].as<long>();
  const double t = c["time"].as<double>();
  const double tol = 1e-9 * std::max(1.0, std::abs(t));
  std::string said;
  std::error_code ec;
  // Later checkpoints first: a rewind cut short (a full disk, a kill) must not
  // leave one that --restart latest would take over the cut series.
  for (const auto& cp : coupler::complete_checkpoints(dir))
    if (coupler::checkpoint_window(cp) > w) {
      fs::remove_all(cp, ec);
      said += fmt::format("  {}: a later checkpoint, removed\n", cp);
    }
  // Checkpoints that an interrupted run left unfinished: begin_checkpoint
  // would reuse their folders.
  std::vector<fs::path> unfinished;
  for (const auto& e : fs::directory_iterator(dir + "/checkpoints", ec))
    if (e.path().extension() == ".partial") unfinished.push_back(e.path());
  for (const auto& p : unfinished) {
    fs::remove_all(p, ec);
    said += fmt::format("  {}: an unfinished checkpoint, removed\n", p.string());
  }
  // The summary and the failure reason of the run being restarted would be
  // read as this one's (a restart that fails before its end writes its own).
  fs::remove(dir + "/summary.json", ec);
  fs::remove(dir + "/logs/FAILED", ec);
  for (const auto& e : fs::directory_iterator(dir + "/logs", ec))
    if (e.path().filename().string().rfind("FAILED.", 0) == 0) fs::remove(e.path(), ec);
  // A series row at t is the checkpoint's window's last: rows after it go.
  for (const auto& e : fs::directory_iterator(dir + "/series", ec))
    // dispersion.csv's first column is the time since a particle crossed
    // the plane, not the run's: it is rewritten whole at every series row.
    if (e.path().extension() == ".csv" && e.path().filename() != "dispersion.csv")
      if (const long n = cut_csv(e.path(), [&](double time) { return time <= t + tol; }); n > 0)
        said += fmt::format("  {}: {} rows after t = {} s removed\n", e.path().string(), n, t);
  // Event logs go back to their sizes at the checkpoint. Without them (a
  // checkpoint from before they were kept, or a log the checkpoint's run did
  // not write) the events at t go too: dem stamps an event with the start
  // of the step that finds it, so the first step after the checkpoint stamps
  // t and the restarted run finds it again.
  // The sizes are those of the checkpoint's own run directory: for a restart
  // into another directory (a second try, or files of another length) the
  // events after t are cut by time instead.
  const bool own = fs::equivalent(fs::path(dir) / "checkpoints", fs::path(restart).parent_path(), ec);
  const auto sizes = own ? event_sizes(restart) : std::map<std::string, std::uintmax_t>{};
  for (const auto& e : fs::directory_iterator(dir + "/events", ec)) {
    if (e.path().extension() != ".csv") continue;
    const auto known = sizes.find(e.path().filename().string());
    const long n = known != sizes.end() ? cut_to_size(e.path(), known->second)
                                        : cut_csv(e.path(), [&](double time) { return time < t - tol; });
    if (n > 0) said += fmt::format("  {}: {} events after the checkpoint removed\n", e.path().string(), n);
  }
  // The snapshots' files go after index.csv and run.xdmf no longer name them
  // (a rewind cut short then leaves files unnamed, not names without files).
  std::vector<fs::path> doomed;
  for (const char* comp : {"fluid", "immersed", "particles"}) {
    const fs::path index = fs::path(dir) / comp / "index.csv";
    if (!fs::exists(index)) continue;
    // The snapshots indexed after t go, and their files (numbered above the
    // last one kept).
    const auto [last, dropped_final] = kept_snapshots(cfg, index, t, tol);
    long gone = 0;
    for (const auto& e : fs::directory_iterator(index.parent_path(), ec)) {
      const std::string n = e.path().filename().string();
      long number = -1;
      if (std::sscanf(n.c_str(), "step_%ld.h5", &number) == 1 && number > last)
        doomed.push_back(e.path()), ++gone;
    }
    cut_index(index, last);
    if (gone > 0)
      said += fmt::format(
          "  {}: {} snapshots removed: those after t = {} s{}\n", index.parent_path().string(), gone, t,
          dropped_final ? ", and the run's last, which fell between two multiples of run.output.every: the "
                          "restarted run writes its number at the next multiple"
                        : "");
  }
  const auto& d = cfg.domain;
  const auto h = d.spacing();
  if (!said.empty())
    output::write_xdmf(dir, {{d.lower[0], d.lower[1], d.lower[2]}, {h[0], h[1], h[2]}, {d.cells[0], d.cells[1], d.cells[2]}});
  for (const auto& p : doomed) fs::remove(p, ec);
  return said;
}

}  // namespace coflow::launcher
