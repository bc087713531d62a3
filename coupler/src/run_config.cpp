#include "coflow/run_config.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "coflow/clock.hpp"
#include "coflow/decomposition.hpp"
#include "coflow/report.hpp"

namespace coflow::config {

void ProbeParams::visit(Visitor& v) {
  v.required("name", name, "column prefix in series/probes.csv (<name>_ux, _uy, _uz, _p; a line's samples "
             "<name>_<k>_ux, ...)");
  v("point", point, "[x, y, z] in m: one sample here");
  v("from", from, "[x, y, z] in m: first sample of a line");
  v("to", to, "[x, y, z] in m: last sample of a line");
  v("points", points, "samples along the line, from and to included (2 or more)");
  if (!v.reading()) return;
  const bool line = v.given("from") || v.given("to");
  if (v.given("point") == line) {
    v.fail("", "give point: [x, y, z] for one sample, or from, to and points for a line");
    return;
  }
  for (const auto& [key, n] : {std::pair{"point", &point}, std::pair{"from", &from}, std::pair{"to", &to}})
    if (v.given(key) && n->values.size() != 3)
      v.fail(key, fmt::format("needs 3 numbers [x, y, z] (got {})", n->values.size()));
  if (line && !(v.given("from") && v.given("to")))
    v.fail("", "a line of samples needs both from and to");
  else if (line && points < 2)
    v.fail("points", fmt::format("a line needs 2 or more points (got {})", points));
  else if (!line && points != 0)
    v.fail("points", "points is for a line (from, to); a point probe has one sample");
}

std::vector<Vec3> ProbeParams::samples() const {
  const auto vec = [](const Numbers& n) { return Vec3{n.values.at(0), n.values.at(1), n.values.at(2)}; };
  if (points == 0) return {vec(point)};
  const Vec3 a = vec(from), b = vec(to);
  std::vector<Vec3> out;
  for (int k = 0; k < points; ++k) {
    const double t = static_cast<double>(k) / static_cast<double>(points - 1);
    out.push_back({a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])});
  }
  return out;
}

void PressureDropParams::visit(Visitor& v) {
  v.required("name", name, "column prefix in series/probes.csv (<name>_p_from, <name>_p_to, <name>_dp)");
  v.required("axis", axis, "the axis across the planes", one_of({"x", "y", "z"}));
  v.required("from", from, "m: position of the first plane along the axis");
  v.required("to", to,
             "m: position of the second plane; dp = p(from) - p(to), each the mean over its plane's fluid "
             "(solid cells excluded)");
}

void OutputParams::visit(Visitor& v) {
  v("dir", dir,
    "output directory (default out/<run.name>): new, empty or an earlier run's (a fresh run empties its "
    "folders)");
  v("every", every, "simulated seconds between snapshots; 0 writes none", non_negative());
  v("fields", fields, "fluid fields written in snapshots",
    each_one_of({"velocity", "pressure", "density", "solid_fraction", "vorticity", "k", "epsilon",
                 "nu_t", "y_plus", "divergence", "momentum_source", "phase"}));
  v("series_every", series_every, "simulated seconds between rows of series/*.csv (auto: = every)",
    positive());
  v("collision_events", collision_events,
    "write events/collisions.csv: time,i,j,angle,relative_speed,normal_speed of each particle pair's first touch "
    "(dpm, dem; angle in degrees between the relative velocity and the line of centres)");
  v("bond_events", bond_events,
    "write events/bonds.csv: time,i,j,mode,normal_force,shear_force of each bond failure (dem; mode tension, "
    "compression or shear; normal_force > 0 compressive)");
  v.list("probes", "fluid probes: velocity and pressure at points or along lines, every series row, into "
         "series/probes.csv (trilinear between cell centres)",
         [&](Visitor& s) {
           probes.emplace_back();
           probes.back().visit(s);
         });
  v.list("pressure_drops",
         "the fluid's mean pressures over two planes and their difference, every series row, into "
         "series/probes.csv",
         [&](Visitor& s) {
           pressure_drops.emplace_back();
           pressure_drops.back().visit(s);
         });
}

void CheckpointParams::visit(Visitor& v) {
  v("every", every, "simulated seconds between checkpoints; 0 writes none", non_negative());
  v("keep", keep, "how many checkpoints to keep", at_least(1));
}

void LaunchParams::visit(Visitor& v) {
  v("bind", bind,
    "process binding of the whole job: core (one core per rank; on an oversubscribed node several ranks share "
    "one, each pinned), none (the kernel moves ranks freely), auto (core where the ranks outnumber the cores, "
    "else the launcher's default; under srun auto leaves the binding to Slurm); mpirun --bind-to, srun --cpu-bind",
    one_of({"auto", "none", "core"}));
  v("mpi_args", mpi_args,
    "extra arguments for mpirun or srun, before the programs (e.g. [--mca, btl_tcp_if_include, eth0]); not "
    "srun's --output or --error (refused under srun and sbatch): the launcher reads the components' output");
  v("start_timeout", start_timeout,
    "seconds the launcher waits for every component's ranks to start (MPI start-up on many nodes can take "
    "minutes) before it stops the launch and names those missing; coupling.timeout bounds the waits after it",
    positive());
  v("stop_grace", stop_grace,
    "seconds a launch stopped by the start watchdog gets to end after SIGTERM before it is killed (SIGKILL), "
    "and the killed launch to let go of its output before the launcher stops reading it (as Slurm's "
    "KillWait; checked about once a second)",
    positive());
}

void RunParams::visit(Visitor& v) {
  v.required("name", name,
             "run name, used for the output directory and the Slurm job: letters, digits and . _ + -");
  v.required("end_time", end_time, "simulated end time in s", positive());
  v.section("output", "snapshots and time series", [&](Visitor& s) { output.visit(s); });
  v.section("checkpoint", "periodic restart files", [&](Visitor& s) { checkpoint.visit(s); });
  v.section("launch", "how the launcher starts the ranks", [&](Visitor& s) { launch.visit(s); });
  v("seed", seed, "seed from which all randomness derives");
  if (v.reading()) {
    // It names the output directory, the Slurm job and the srun program file's
    // paths: letters, digits and . _ + - only (no quotes, #, % or spaces,
    // which sbatch and srun --multi-prog would read otherwise).
    if (name.empty() ||
        name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789._+-") !=
            std::string::npos ||
        name == "." || name == "..")
      v.fail("name",
             fmt::format("must be a plain word without spaces or slashes: letters, digits and . _ + - "
                         "(got '{}')",
                         name));
  }
}

void CouplingParams::visit(Visitor& v) {
  std::string name = scheme_name(scheme);
  v("scheme", name,
    "coupling scheme: serial-explicit (the particles step on this window's loads) or parallel-explicit (on the "
    "previous window's, while the fluid computes this window's)",
    one_of(scheme_names()));
  if (v.reading()) {
    try {
      scheme = scheme_from_name(name);
    } catch (const std::invalid_argument&) {
      // reported by one_of above
    }
  }
  v("window", window, "coupling window in s (auto: the fluid's time step, shortened by at most 10 % (lbm: a slightly lower tau at the same viscosity) so that run.output.every is a whole number of windows and snapshots fall at its exact multiples)", positive());
  v("timeout", timeout, "seconds a rank waits for a partner before the whole run is aborted",
    positive());
}

void DomainParams::visit(Visitor& v) {
  v.required("lower", lower, "lower corner of the box, m");
  v.required("upper", upper, "upper corner of the box, m");
  v.required("cells", cells, "fluid grid cells per axis; 2D runs use cells[2] = 1", positive());
  v("periodic", periodic, "periodicity per axis");
  if (v.reading()) {
    // 2^53: every cell count (the grid's, a block's, an offset into a field)
    // stays exact in a double and far inside a 64-bit integer.
    constexpr double kMostCells = 9007199254740992.0;
    if (const double total = double(cells[0]) * cells[1] * cells[2]; total > kMostCells)
      v.fail("cells",
             fmt::format("{} x {} x {} = {:.3g} cells is more than any machine holds (at most 2^53 = "
                         "{:.3g}); check the numbers",
                         cells[0], cells[1], cells[2], total, kMostCells));
    for (int d = 0; d < 3; ++d)
      if (!(upper[d] > lower[d])) {
        v.fail("upper", fmt::format("must exceed lower on every axis (axis {}: lower {} upper {})",
                                    "xyz"[d], lower[d], upper[d]));
        break;
      }
  }
}

Vec3 DomainParams::spacing() const {
  return {(upper[0] - lower[0]) / cells[0], (upper[1] - lower[1]) / cells[1],
          (upper[2] - lower[2]) / cells[2]};
}

std::string Config::output_dir() const {
  return run.output.dir.empty() ? "out/" + run.name : run.output.dir;
}

void visit_component_common(Visitor& v, const ComponentSchema& schema, ComponentInfo& info) {
  std::vector<std::string> names = schema.variants;
  names.push_back("none");
  if (schema.variants.empty())  // an open schema: any name
    v.required(schema.selector, info.variant, "which variant runs this component");
  else
    v.required(schema.selector, info.variant, "which variant runs this component", one_of(names));
  v("ranks", info.ranks, "MPI ranks of this component", at_least(1));
  // The plain reference variants (the test oracles) are serial by design.
  const std::string suffix = "-reference";
  const bool known = std::find(schema.variants.begin(), schema.variants.end(), info.variant) != schema.variants.end();
  if (v.reading() && known && info.ranks != 1 && info.variant.size() > suffix.size() &&
      info.variant.compare(info.variant.size() - suffix.size(), suffix.size(), suffix) == 0)
    v.fail("ranks",
           fmt::format("{} is serial (the plain reference, the test oracle): set ranks: 1 (got {}), or "
                       "use {}: {}",
                       info.variant, info.ranks, schema.selector,
                       info.variant.substr(0, info.variant.size() - suffix.size())));
  v("decomposition", info.decomposition,
    "blocks per axis of this component's share of the domain (auto: balanced)", positive());
  if (v.reading() && !info.decomposition.is_auto) {
    const auto& d = info.decomposition.value;
    if (d[0] * d[1] * d[2] != info.ranks)
      v.fail("decomposition", fmt::format("product {}x{}x{} = {} must equal ranks ({})", d[0], d[1],
                                          d[2], d[0] * d[1] * d[2], info.ranks));
  }
}

static void visit_top(Visitor& v, Config& cfg, const Catalog& catalog) {
  v.section("run", "the run: name, end time, output", [&](Visitor& s) { cfg.run.visit(s); });
  v.section("coupling", "how components exchange data", [&](Visitor& s) { cfg.coupling.visit(s); });
  const std::size_t before = v.problem_count();
  v.section("domain", "the global box and the fluid grid", [&](Visitor& s) { cfg.domain.visit(s); });
  // A domain whose box or grid is unusable (no cells, a NaN corner, left out)
  // sets off the components' checks against it (one-cell axes, cubic cells,
  // 3D only): report it alone. (An unknown key beside a usable box does not.)
  if (v.problems_since(before, {"domain", "domain.lower", "domain.upper", "domain.cells"}))
    v.quiet_cross_checks();
  v("gravity", cfg.gravity, "gravitational acceleration, m/s^2");
  for (const auto& schema : catalog) {
    ComponentInfo info;
    info.section = schema.section;
    bool present = false;
    v.section(schema.section, schema.doc,
              [&](Visitor& s) {
                if (s.reading() && !present) return;  // component not in this run
                schema.visit(s, cfg, info);
              },
              &present);
    info.present = present && info.variant != "none";
    if (info.present) cfg.components[schema.section] = info;
  }
}

// Every requested snapshot field must be one that a present component's
// variant writes (a field nobody writes would silently be missing).
// Each component's ranks must split the grid into blocks of at least one cell;
// otherwise say the most ranks that can.
static void check_decompositions(Reader& r, const Config& cfg) {
  const auto& d = cfg.domain;
  const coupler::Index3 cells{d.cells[0], d.cells[1], d.cells[2]};
  for (const auto& [section, info] : cfg.components) {
    std::array<int, 3> dims{0, 0, 0};
    if (!info.decomposition.is_auto) dims = info.decomposition.value;
    try {
      coupler::Decomposition(cells, info.ranks, dims, d.periodic);
    } catch (const std::invalid_argument& e) {
      if (!info.decomposition.is_auto) {  // the blocks given do not fit: say so, not a rank count
        r.fail(
            section + ".decomposition",
            fmt::format(
                "{} x {} x {} blocks cannot split the {}x{}x{} grid ({}); give fewer blocks along that axis "
                "(their product is the rank count) or leave decomposition out",
                dims[0], dims[1], dims[2], cells[0], cells[1], cells[2], e.what()));
        continue;
      }
      int most = static_cast<int>(std::min<long>(info.ranks - 1, cells[0] * cells[1] * cells[2]));
      for (; most > 1; --most) {
        try {
          coupler::Decomposition(cells, most, {0, 0, 0}, d.periodic);
          break;
        } catch (const std::invalid_argument&) {
        }
      }
      r.fail(section + ".ranks", fmt::format("{} ranks cannot split the {}x{}x{} grid ({}); at most {} can", info.ranks,
                                             cells[0], cells[1], cells[2], e.what(), most));
    }
  }
}

// A window given in the file must leave a count of windows a run can hold,
// and the output intervals a count of snapshots, rows and checkpoints.
static void check_window_count(Reader& r, const Config& cfg) {
  const auto& o = cfg.run.output;
  const std::pair<const char*, double> intervals[] = {
      {"coupling.window", cfg.coupling.window.is_auto ? 0.0 : cfg.coupling.window.value},
      {"run.output.every", o.every},
      {"run.output.series_every", o.series_every.is_auto ? 0.0 : o.series_every.value},
      {"run.checkpoint.every", cfg.run.checkpoint.every}};
  for (const auto& [key, every] : intervals) {
    const double count = cfg.run.end_time / every;
    if (!(every > 0) || count <= coupler::kMostWindows) continue;
    r.fail("run.end_time",
           fmt::format("{} s is {:.3g} intervals of {} s ({}), more than the {:.0e} a run can count: "
                       "shorten run.end_time or lengthen {}",
                       number(cfg.run.end_time), count, number(every), key, coupler::kMostWindows, key));
    return;
  }
}

// A window given in the file must end the run at run.end_time: the last
// window would otherwise carry it past (end_time 1.0 in windows of 0.3 ran to
// 1.2 s, its summary still saying 1.0).
static void check_window_divides(Reader& r, const Config& cfg) {
  if (cfg.coupling.window.is_auto) return;
  const double w = cfg.coupling.window.value, end = cfg.run.end_time, count = end / w;
  const double windows = std::max(1.0, std::ceil(count - coupler::kReach));  // the clock's count
  if (windows * w - end <= 1e-6 * end) return;  // past the end by a millionth of the run at most
  r.fail(
      "coupling.window",
      fmt::format("{} s does not divide run.end_time = {} s into whole windows ({:.6g}): the run would stop "
                  "at {} s; make run.end_time a multiple of the window (e.g. {} s) or leave "
                  "coupling.window: auto",
                  number(w), number(end), count, number(windows * w), number(windows * w)));
}

// A window writes at most one snapshot and one series row: a given window
// longer than an output interval skipped snapshot numbers (every 0.004 s in
// windows of 0.01 s wrote 0, 2, 5, 7, 10) and rows.
static void check_window_outputs(Reader& r, const Config& cfg) {
  if (cfg.coupling.window.is_auto) return;
  const double w = cfg.coupling.window.value;
  const auto& o = cfg.run.output;
  const std::pair<const char*, double> intervals[] = {
      {"run.output.every", o.every},
      {"run.output.series_every", o.series_every.is_auto ? 0.0 : o.series_every.value}};
  for (const auto& [key, e] : intervals)
    if (e > 0 && e < w * (1 - 1e-9))
      r.fail(key,
             fmt::format("{} s is shorter than coupling.window = {} s: a window writes one snapshot and one "
                         "series row at most, so some would be skipped; make it {} s or longer, or shorten "
                         "the window",
                         number(e), number(w), number(w)));
}

// A fresh run empties its output directory's fluid/, particles/, logs/, ...
// folders: a directory that holds files but is no coflow run's is refused, so
// that run.output.dir: . in a source tree or a home directory deletes nothing
// of the user's. A run's marks are the files only coflow writes there
// (summary.json, run.xdmf, the launcher's lock, an sbatch script) or a
// component's log (a config.yaml or a logs/ folder alone could be the user's).
static bool holds_a_run(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  for (const char* mark : {"summary.json", "run.xdmf", ".coflow.lock", "job.sbatch", "logs/fluid.log",
                           "logs/particles.log", "logs/immersed.log"})
    if (fs::exists(fs::path(dir) / mark, ec)) return true;
  return false;
}

static void check_output_dir(Reader& r, const Config& cfg) {
  namespace fs = std::filesystem;
  const std::string dir = cfg.output_dir();
  std::error_code ec;
  if (!fs::exists(dir, ec)) return;
  if (!fs::is_directory(dir, ec)) {
    r.fail("run.output.dir",
           fmt::format("'{}' is a file, not a directory: choose a new or empty directory", dir));
    return;
  }
  if (fs::is_empty(dir, ec) || holds_a_run(dir)) return;
  r.fail("run.output.dir",
         fmt::format(
             "'{}' holds files and is not a coflow run directory (it has no summary.json, run.xdmf, "
             ".coflow.lock, job.sbatch or component log): a run there would delete its fluid/, particles/, "
             "immersed/, series/, events/, logs/ and checkpoints/ folders; choose a new or empty directory",
             dir));
}

// Probes and pressure drops sample the fluid inside the domain; their names
// are unique column prefixes.
static void check_probes(Reader& r, const Config& cfg, const Catalog& catalog) {
  const auto& o = cfg.run.output;
  if (o.probes.empty() && o.pressure_drops.empty()) return;
  const std::string list = o.probes.empty() ? "run.output.pressure_drops" : "run.output.probes";
  if (!cfg.has("fluid")) {
    r.fail(list, "probes sample the fluid, and this run has none: add a fluid section or remove them");
    return;
  }
  for (const auto& schema : catalog) {
    if (schema.section != "fluid" || !schema.writes) continue;
    const std::string& variant = cfg.component("fluid").variant;
    const auto writes = schema.writes(variant);
    for (const char* f : {"velocity", "pressure"})
      if (!writes.empty() && std::find(writes.begin(), writes.end(), f) == writes.end())
        r.fail(list, fmt::format("probes sample velocity and pressure; fluid.solver {} does not write {}", variant, f));
  }
  const auto& d = cfg.domain;
  std::vector<std::string> names;
  const auto inside = [&](const Vec3& x) {
    for (int a = 0; a < 3; ++a)
      if (!(x[a] >= d.lower[a] && x[a] <= d.upper[a])) return false;
    return true;
  };
  const auto check_name = [&](const std::string& at, const std::string& name) {
    if (name.empty() || name.find_first_of(", \t\"\n\r") != std::string::npos)
      r.fail(at + ".name", fmt::format("'{}' is not a plain word (it names CSV columns)", name));
    if (std::find(names.begin(), names.end(), name) != names.end())
      r.fail(at + ".name", fmt::format("'{}' names another probe too; give each its own name", name));
    names.push_back(name);
  };
  // A line probe's columns are <name>_<k>_ux ...: a point probe named so
  // would write the same columns (series/probes.csv with two of each).
  std::map<std::string, std::size_t> lines;  // <name>_<k>, k = 0 .. points - 1 -> the line's index
  for (std::size_t i = 0; i < o.probes.size(); ++i)
    for (int k = 0; k < o.probes[i].points; ++k) lines.emplace(fmt::format("{}_{}", o.probes[i].name, k), i);
  for (std::size_t i = 0; i < o.probes.size(); ++i) {
    const std::string key = fmt::format("run.output.probes[{}]", i);
    check_name(key, o.probes[i].name);
    if (const auto l = lines.find(o.probes[i].name); o.probes[i].points == 0 && l != lines.end())
      r.fail(key + ".name", fmt::format("'{}' is also a column prefix of the line probe {} (its points are "
                                        "<name>_0 to <name>_{}): give this probe another name",
                                        o.probes[i].name, fmt::format("run.output.probes[{}]", l->second),
                                        o.probes[l->second].points - 1));
    // The domain is a box: a line lies in it when both its ends do.
    const ProbeParams& p = o.probes[i];
    const std::vector<Vec3> xs = p.samples();
    for (const auto& [k, x] : p.points == 0 ? std::vector<std::pair<std::string, Vec3>>{{"point", xs.front()}}
                                            : std::vector<std::pair<std::string, Vec3>>{{"from", xs.front()},
                                                                                        {"to", xs.back()}})
      if (!inside(x))
        r.fail(key + "." + k, fmt::format("[{}, {}, {}] lies outside the domain, [{}, {}, {}] to [{}, {}, {}]", x[0],
                                          x[1], x[2], d.lower[0], d.lower[1], d.lower[2], d.upper[0], d.upper[1],
                                          d.upper[2]));
  }
  for (std::size_t i = 0; i < o.pressure_drops.size(); ++i) {
    const auto& p = o.pressure_drops[i];
    const std::string key = fmt::format("run.output.pressure_drops[{}]", i);
    check_name(key, p.name);
    const int a = p.axis_index();
    for (const auto& [k, x] : {std::pair{"from", p.from}, std::pair{"to", p.to}})
      if (x < d.lower[a] || x > d.upper[a])
        r.fail(key + "." + k, fmt::format("{} m lies outside the domain along {} ({} to {} m)", x, p.axis, d.lower[a],
                                          d.upper[a]));
  }
}

static void check_output_fields(Reader& r, const Config& cfg, const Catalog& catalog) {
  for (const auto& schema : catalog) {
    if (!cfg.has(schema.section) || !schema.writes) continue;
    const std::string& variant = cfg.component(schema.section).variant;
    const auto writes = schema.writes(variant);
    if (writes.empty()) continue;
    for (const auto& f : cfg.run.output.fields)
      if (std::find(writes.begin(), writes.end(), f) == writes.end())
        r.fail("run.output.fields", fmt::format("{}.{} {} does not write '{}'; it writes: {}", schema.section,
                                                schema.selector, variant, f, fmt::join(writes, ", ")));
  }
}

Catalog open_catalog() {
  Catalog c;
  for (const auto& [section, selector] : std::vector<std::pair<std::string, std::string>>{
           {"fluid", "solver"}, {"immersed", "method"}, {"particles", "solver"}}) {
    ComponentSchema s;
    s.section = section;
    s.selector = selector;
    s.doc = "the " + section + " component (its keys are checked by the launcher)";
    s.visit = [s](Visitor& v, const Config&, ComponentInfo& info) {
      visit_component_common(v, s, info);
      v.accept_other_keys();
    };
    c.push_back(s);
  }
  return c;
}

Config parse_config_node(YAML::Node root, const std::string& file, const Catalog& catalog) {
  Config cfg;
  cfg.file = file;
  // The hash of what was read (file and overrides), not of the resolved file:
  // a component that reads the file with another catalogue (open_catalog())
  // fills in other defaults but read the same configuration.
  cfg.hash = hash_text(YAML::Dump(root));
  Reader r(root, file);
  visit_top(r, cfg, catalog);
  r.finish();
  if (r.problems().empty() && cfg.components.empty())
    r.fail("", "no component to run: add at least one of the sections fluid, immersed, particles");
  // immersed couples particles to a fluid; its method ibm forces the fluid alone.
  if (r.problems().empty() && cfg.has("immersed") &&
      (!cfg.has("fluid") || (!cfg.has("particles") && cfg.component("immersed").variant != "ibm")))
    r.fail("immersed", cfg.has("fluid") ? "the immersed component couples a fluid and particles: add both sections "
                                          "(or method: ibm, immersed bodies for the fluid alone)"
                                        : "the immersed component acts on a fluid: add the fluid section");
  // Whether the components can work together at all comes first: a field
  // they do not write or a probe they cannot serve follows from that.
  cfg.resolved = r.resolved();
  if (r.problems().empty()) check_contracts(r, cfg, catalog);
  if (r.problems().empty()) check_output_fields(r, cfg, catalog);
  if (r.problems().empty()) check_probes(r, cfg, catalog);
  if (r.problems().empty()) check_decompositions(r, cfg);
  if (r.problems().empty()) check_window_count(r, cfg);
  if (r.problems().empty()) check_window_divides(r, cfg);
  if (r.problems().empty()) check_window_outputs(r, cfg);
  if (r.problems().empty()) check_output_dir(r, cfg);
  for (const auto& schema : catalog)
    if (r.problems().empty() && schema.check && cfg.has(schema.section))
      schema.check(r, cfg, cfg.component(schema.section).variant);
  r.check();
  for (const auto& schema : catalog)
    if (schema.resolve && cfg.has(schema.section)) schema.resolve(cfg, cfg.component(schema.section).variant);
  cfg.resolved["run"]["output"]["dir"] = cfg.output_dir();
  return cfg;
}

// A problem in a value that --set gave has no place in the file (the value's
// node would say 1:1): it names the --set instead.
static YAML::Node dotted_node(const YAML::Node& root, const std::string& dotted_path);

static void point_at_overrides(std::vector<Problem>& problems, const std::vector<std::string>& overrides,
                               const YAML::Node& file_root) {
  for (Problem& p : problems)
    for (auto it = overrides.rbegin(); it != overrides.rend(); ++it) {  // the last --set of a key wins
      const std::string& o = *it;
      const std::string key = o.substr(0, o.find('='));
      const bool under = p.path == key || (p.path.rfind(key, 0) == 0 && p.path.size() > key.size() &&
                                           (p.path[key.size()] == '.' || p.path[key.size()] == '['));
      const bool created = !p.path.empty() && key.rfind(p.path + ".", 0) == 0 &&
                           p.path.find('[') == std::string::npos &&
                           !dotted_node(file_root, p.path);  // a section the --set created
      if (!under && !created) continue;
      p.line = p.column = 0;
      p.message += fmt::format(" (from --set {})", o);
      break;
    }
}

Config parse_config(const std::string& file, const Catalog& catalog,
                    const std::vector<std::string>& overrides) {
  YAML::Node root = load_yaml_file(file);
  for (const auto& o : overrides) apply_override(root, o);
  try {
    return parse_config_node(root, file, catalog);
  } catch (const ConfigError& e) {
    if (overrides.empty()) throw;
    std::vector<Problem> problems = e.problems();
    point_at_overrides(problems, overrides, load_yaml_file(file));
    throw ConfigError(std::move(problems));
  }
}

void describe_config(Visitor& v, const Catalog& catalog) {
  Config cfg;
  visit_top(v, cfg, catalog);
}

// By recursion on const nodes: reassigning a YAML::Node would rebind the tree.
static YAML::Node node_at(const YAML::Node& n, const std::vector<std::string>& path, std::size_t i) {
  if (i == path.size()) return n;
  if (!n.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
  const YAML::Node child = n[path[i]];
  return child ? node_at(child, path, i + 1) : YAML::Node(YAML::NodeType::Undefined);
}

std::string resolved_text(const Config& cfg, const std::vector<std::string>& path) {
  const YAML::Node n = node_at(cfg.resolved, path, 0);
  return n.IsScalar() ? n.Scalar() : "";
}

double to_number(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size())
    throw std::invalid_argument(fmt::format("'{}' is not a number", text));
  return v;
}

double resolved_number(const Config& cfg, const std::vector<std::string>& path, double fallback) {
  try {
    const double v = to_number(resolved_text(cfg, path));
    return std::isfinite(v) ? v : fallback;
  } catch (const std::invalid_argument&) {
    return fallback;
  }
}

bool two_phase_fluid(const Config& cfg) {
  const YAML::Node n = node_at(cfg.resolved, {"fluid", "two_phase"}, 0);
  return n.IsMap();
}

bool point_coupling(const Config& cfg) {
  const std::string method = resolved_text(cfg, {"immersed", "method"});
  return method == "point" ||
         (method == "ibm" && resolved_text(cfg, {"immersed", "ibm", "particles"}) == "point");
}

static YAML::Node dotted_node(const YAML::Node& root, const std::string& dotted_path) {
  std::vector<std::string> path;
  std::string rest = dotted_path;
  while (!rest.empty()) {
    const auto dot = rest.find('.');
    path.push_back(rest.substr(0, dot));
    rest = dot == std::string::npos ? "" : rest.substr(dot + 1);
  }
  return node_at(root, path, 0);
}

YAML::Node resolved_node(const Config& cfg, const std::string& dotted_path) {
  return dotted_node(cfg.resolved, dotted_path);
}

std::uint64_t hash_text(const std::string& text) {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

}  // namespace coflow::config
