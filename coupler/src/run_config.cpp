#include "coflow/run_config.hpp"

#include "coflow/decomposition.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <fmt/format.h>
#include <fmt/ranges.h>

namespace coflow::config {

void OutputParams::visit(Visitor& v) {
  v("dir", dir, "output directory (default out/<run.name>)");
  v("every", every, "simulated seconds between snapshots; 0 writes none", non_negative());
  v("fields", fields, "fluid fields written in snapshots",
    each_one_of({"velocity", "pressure", "density", "solid_fraction", "vorticity", "k", "epsilon",
                 "momentum_source"}));
  v("series_every", series_every, "simulated seconds between rows of series/*.csv (auto: = every)",
    positive());
  v("collision_events", collision_events,
    "write events/collisions.csv: time,i,j,angle,relative_speed,normal_speed of each particle pair's first touch "
    "(dpm, dem; angle in degrees between the relative velocity and the line of centres)");
  v("bond_events", bond_events,
    "write events/bonds.csv: time,i,j,mode,normal_force,shear_force of each bond failure (dem; mode tension, "
    "compression or shear; normal_force > 0 compressive)");
}

void CheckpointParams::visit(Visitor& v) {
  v("every", every, "simulated seconds between checkpoints; 0 writes none", non_negative());
  v("keep", keep, "how many checkpoints to keep", at_least(1));
}

void RunParams::visit(Visitor& v) {
  v.required("name", name, "run name, used for the output directory");
  v.required("end_time", end_time, "simulated end time in s", positive());
  v.section("output", "snapshots and time series", [&](Visitor& s) { output.visit(s); });
  v.section("checkpoint", "periodic restart files", [&](Visitor& s) { checkpoint.visit(s); });
  v("seed", seed, "seed from which all randomness derives");
  if (v.reading()) {
    if (name.empty() || name.find_first_of("/\\ \t") != std::string::npos || name == "." || name == "..")
      v.fail("name", fmt::format("must be a plain word without spaces or slashes (got '{}')", name));
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
  v("window", window, "coupling window in s (auto: the fluid time step)", positive());
  v("timeout", timeout, "seconds a rank waits for a partner before the whole run is aborted",
    positive());
}

void DomainParams::visit(Visitor& v) {
  v.required("lower", lower, "lower corner of the box, m");
  v.required("upper", upper, "upper corner of the box, m");
  v.required("cells", cells, "fluid grid cells per axis; 2D runs use cells[2] = 1", positive());
  v("periodic", periodic, "periodicity per axis");
  if (v.reading()) {
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
  v.section("domain", "the global box and the fluid grid", [&](Visitor& s) { cfg.domain.visit(s); });
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
  if (r.problems().empty() && cfg.has("immersed") && (!cfg.has("fluid") || !cfg.has("particles")))
    r.fail("immersed", "the immersed component couples a fluid and particles: add both sections");
  if (r.problems().empty()) check_output_fields(r, cfg, catalog);
  if (r.problems().empty()) check_decompositions(r, cfg);
  cfg.resolved = r.resolved();
  if (r.problems().empty()) check_contracts(r, cfg, catalog);
  r.check();
  for (const auto& schema : catalog)
    if (schema.resolve && cfg.has(schema.section)) schema.resolve(cfg, cfg.component(schema.section).variant);
  cfg.resolved["run"]["output"]["dir"] = cfg.output_dir();
  return cfg;
}

Config parse_config(const std::string& file, const Catalog& catalog,
                    const std::vector<std::string>& overrides) {
  YAML::Node root = load_yaml_file(file);
  for (const auto& o : overrides) apply_override(root, o);
  return parse_config_node(root, file, catalog);
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

YAML::Node resolved_node(const Config& cfg, const std::string& dotted_path) {
  std::vector<std::string> path;
  std::string rest = dotted_path;
  while (!rest.empty()) {
    const auto dot = rest.find('.');
    path.push_back(rest.substr(0, dot));
    rest = dot == std::string::npos ? "" : rest.substr(dot + 1);
  }
  return node_at(cfg.resolved, path, 0);
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
