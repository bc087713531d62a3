// The pre-run report, like OpenFOAM's checkMesh: what a run will be before it
// starts (grid spacing, steps, Mach and Reynolds numbers, resolution of the
// particles, memory, an estimate of the wall time), with warnings for what is
// likely wrong. `coflow validate` prints it as YAML comments; `coflow run`
// prints it before the launch; with --strict a warning is an error (exit 2).
#pragma once

#include <string>
#include <vector>

namespace coflow::config {

struct Config;
struct ComponentSchema;

struct Report {
  struct Line {
    std::string section, label, value;
  };
  std::vector<Line> lines;
  std::vector<std::string> warnings;  // "section: what, and how to fix it"
  double wall_seconds = 0.0;  // the largest component estimate of the run's wall time; 0: none

  void estimate_wall(double seconds) { wall_seconds = seconds > wall_seconds ? seconds : wall_seconds; }

  void add(const std::string& section, const std::string& label, const std::string& value) {
    lines.push_back({section, label, value});
  }
  void warn(const std::string& section, const std::string& message) { warnings.push_back(section + ": " + message); }
  // Every line as "  section  label  value", then "warning: ..." lines; each
  // line prefixed by `prefix` ("# " keeps `coflow validate`'s output YAML).
  std::string text(const std::string& prefix = "") const;
};

// The run's report: the common part (windows, ranks) and each present
// component's (ComponentSchema::report).
Report pre_run_report(const Config& cfg, const std::vector<ComponentSchema>& catalog);

// Numbers for a report: "0.0123", "1.5e+06"; durations: "42 s", "3.5 min", "2.1 h", "4.2 days".
std::string number(double x);
std::string duration(double seconds);

}  // namespace coflow::config
