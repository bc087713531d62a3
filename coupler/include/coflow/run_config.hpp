// The top-level configuration: run, coupling, domain, gravity, plus one section
// per component whose schema the component contributes through a `Catalog`.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "coflow/config.hpp"
#include "coflow/contract.hpp"
#include "coflow/report.hpp"

namespace coflow::config {

// A probe of the fluid (series/probes.csv): velocity and pressure at a point,
// or at `points` points evenly spaced from `from` to `to` (a line), trilinear
// between cell centres.
struct ProbeParams {
  std::string name;
  Numbers point, from, to;  // 3 numbers each where given (a list left out stays out of the resolved file)
  int points = 0;           // a line's samples; 0 for a point probe
  void visit(Visitor& v);
  // The sample positions, in order.
  std::vector<Vec3> samples() const;
};

// The mean pressure over two planes across `axis` and their difference.
struct PressureDropParams {
  std::string name;
  std::string axis;  // x, y or z
  double from = 0.0, to = 0.0;  // plane positions along axis, m
  void visit(Visitor& v);
  int axis_index() const { return axis == "y" ? 1 : axis == "z" ? 2 : 0; }
};

struct OutputParams {
  std::string dir;                 // default out/<run.name>
  double every = 0.0;              // s between snapshots; 0 = none
  StringList fields{"velocity", "pressure"};
  AutoDouble series_every;         // auto = every
  bool collision_events = false;
  bool bond_events = false;
  std::vector<ProbeParams> probes;
  std::vector<PressureDropParams> pressure_drops;
  void visit(Visitor& v);
};

struct CheckpointParams {
  double every = 0.0;  // s; 0 = none
  int keep = 2;
  void visit(Visitor& v);
};

// How the launcher starts the ranks (mpirun or srun): the binding of the
// whole job (both launch every component in one job, one binding for all) and
// extra arguments.
struct LaunchParams {
  std::string bind = "auto";  // auto | none | core
  StringList mpi_args;
  double start_timeout = 300.0;  // s: the launcher's start watchdog (coupling.timeout is the ranks' own)
  double stop_grace = 10.0;      // s: SIGTERM -> SIGKILL of a stopped launch, and SIGKILL -> the pipe left
  void visit(Visitor& v);
};

struct RunParams {
  std::string name;
  double end_time = 0.0;
  OutputParams output;
  CheckpointParams checkpoint;
  LaunchParams launch;
  std::uint64_t seed = 12345;
  void visit(Visitor& v);
};

struct CouplingParams {
  Scheme scheme = Scheme::serial_explicit;
  AutoDouble window;
  double timeout = 300.0;  // s a rank may wait for a partner before the run is aborted
  void visit(Visitor& v);
};

struct DomainParams {
  Vec3 lower{0, 0, 0};
  Vec3 upper{1, 1, 1};
  Int3 cells{1, 1, 1};
  Bool3 periodic{false, false, false};
  void visit(Visitor& v);
  Vec3 spacing() const;
  bool two_dimensional() const { return cells[2] == 1; }
};

// The section of a component that the coupler needs to know about, whatever
// the variant: its variant name and its rank layout.
struct ComponentInfo {
  std::string section;   // "fluid", "immersed", "particles"
  std::string variant;   // solver or method name
  int ranks = 1;
  AutoInt3 decomposition;
  bool present = false;
};

struct Config;

// How a component declares its section. `visit` reads the whole section
// (including `solver`/`method`, `ranks`, `decomposition`) and fills `info`.
struct ComponentSchema {
  std::string section;
  std::string selector;  // "solver" or "method"
  std::vector<std::string> variants;
  std::string doc;
  std::function<void(Visitor&, const Config&, ComponentInfo&)> visit;
  // The snapshot fields (run.output.fields) a variant writes; empty: not known
  // (external), so not checked.
  std::function<std::vector<std::string>(const std::string& variant)> writes;
  // What a variant provides, needs and which schemes it runs (coflow/contract.hpp);
  // called once the whole file is read, so it may depend on the variant's keys.
  // Unset: an open contract (nothing checked).
  std::function<Contract(const Config&, const std::string& variant)> contract;
  // The component's part of the pre-run report (coflow/report.hpp); unset: none.
  std::function<void(const Config&, const std::string& variant, Report&)> report;
  // Write into cfg.resolved what the variant takes by default but the schema
  // leaves out (e.g. the boundaries of faces not given), so that the resolved
  // file shows it. Unset: nothing to add.
  std::function<void(Config&, const std::string& variant)> resolve;
  // Checks that span sections (a key of this component against another's, or
  // against a subsection of its own), run once the whole file is read and
  // resolved and the contracts hold; failures go to `v` at dotted paths from
  // the top ("fluid.fv.refinement"). Unset: none.
  std::function<void(Visitor& v, const Config&, const std::string& variant)> check;
};

using Catalog = std::vector<ComponentSchema>;

// The three component sections with only their common keys checked (selector,
// ranks, decomposition) and any other key accepted: what a component built
// outside the tree reads the file with, linking libcoflow alone. The launcher
// has checked the whole file against the full catalogue before any rank starts.
Catalog open_catalog();

struct Config {
  std::string file;                    // as given by the user
  RunParams run;
  CouplingParams coupling;
  DomainParams domain;
  Vec3 gravity{0, 0, 0};
  std::map<std::string, ComponentInfo> components;  // by section name; only present ones
  YAML::Node resolved;                 // every key, defaults filled in
  std::uint64_t hash = 0;              // of the configuration as read (file and overrides)

  bool has(const std::string& section) const { return components.count(section) != 0; }
  const ComponentInfo& component(const std::string& section) const { return components.at(section); }
  std::string output_dir() const;
};

// The standard order of components in an MPMD launch.
inline const std::vector<std::string>& component_order() {
  static const std::vector<std::string> order{"fluid", "immersed", "particles"};
  return order;
}

// Read, validate and resolve a configuration. Throws ConfigError listing every
// problem. `overrides` are `key.path=value` assignments applied first.
Config parse_config(const std::string& file, const Catalog& catalog,
                    const std::vector<std::string>& overrides = {});
Config parse_config_node(YAML::Node root, const std::string& file, const Catalog& catalog);

// Visit the whole schema (for `coflow variants` and docs/config.md).
void describe_config(Visitor& v, const Catalog& catalog);

// Declare the common keys of a component section (selector, ranks, decomposition).
void visit_component_common(Visitor& v, const ComponentSchema& schema, ComponentInfo& info);

// The node at a dotted path of the resolved configuration (an undefined node
// where there is none). It never modifies the configuration: assigning one
// YAML::Node to another would rebind the shared tree.
YAML::Node resolved_node(const Config& cfg, const std::string& dotted_path);

// Re-read a section of a resolved configuration into a Params struct.
template <class P>
P read_section(const Config& cfg, const std::string& path_in_resolved, const std::string& path_label) {
  P p;
  Reader r(resolved_node(cfg, path_in_resolved), cfg.file, path_label);
  p.visit(r);
  r.finish();
  r.check();
  return p;
}

std::uint64_t hash_text(const std::string& text);

// The scalar at a path of the resolved configuration, or "" where there is none.
std::string resolved_text(const Config& cfg, const std::vector<std::string>& path);
// The finite number there (strtod: a subnormal such as 1e-320 is read, not
// thrown as std::stod throws it), or `fallback` where there is none.
double resolved_number(const Config& cfg, const std::vector<std::string>& path, double fallback);

// The whole of `text` as a double by strtod (every double written with 17
// digits reads back to the bit, subnormals included, where std::stod throws
// out_of_range on them); std::invalid_argument naming it where it is not one.
double to_number(const std::string& text);

// The fluid carries two phases (fluid.two_phase is given).
bool two_phase_fluid(const Config& cfg);
// Whether the immersed component couples point particles to the fluid (the
// point exchanges of docs/protocol.md): immersed.method point, or ibm with
// immersed.ibm.particles: point (bodies and point particles in one run).
bool point_coupling(const Config& cfg);

}  // namespace coflow::config
