#include "coflow/report.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "coflow/run_config.hpp"

namespace coflow::config {

std::string number(double x) { return fmt::format("{:.4g}", x); }

std::string duration(double seconds) {
  if (seconds < 120.0) return fmt::format("{:.2g} s", seconds);
  if (seconds < 7200.0) return fmt::format("{:.2g} min", seconds / 60.0);
  if (seconds < 172800.0) return fmt::format("{:.2g} h", seconds / 3600.0);
  return fmt::format("{:.3g} days", seconds / 86400.0);
}

std::string Report::text(const std::string& prefix) const {
  std::size_t w = 0;
  for (const auto& l : lines) w = std::max(w, l.label.size());
  std::string out, section;
  for (const auto& l : lines) {
    if (l.section != section) {
      section = l.section;
      out += fmt::format("{}{}:\n", prefix, section);
    }
    out += fmt::format("{}  {:<{}}  {}\n", prefix, l.label, w, l.value);
  }
  for (const auto& m : warnings) out += fmt::format("{}warning: {}\n", prefix, m);
  return out;
}

Report pre_run_report(const Config& cfg, const std::vector<ComponentSchema>& catalog) {
  Report r;
  std::string comps;
  for (const auto& [name, info] : cfg.components)
    comps += fmt::format("{}{} {} on {} rank{}", comps.empty() ? "" : ", ", name, info.variant, info.ranks,
                         info.ranks == 1 ? "" : "s");
  r.add("run", "components", comps);
  r.add("run", "end time", number(cfg.run.end_time) + " s");
  r.add("run", "coupling", fmt::format("{}, window {}", scheme_name(cfg.coupling.scheme),
                                       cfg.coupling.window.is_auto ? std::string("auto (the fluid step)")
                                                                   : number(cfg.coupling.window.value) + " s"));
  for (const auto& schema : catalog)
    if (cfg.has(schema.section) && schema.report) schema.report(cfg, cfg.component(schema.section).variant, r);
  return r;
}

}  // namespace coflow::config
