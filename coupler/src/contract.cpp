#include "coflow/contract.hpp"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "coflow/run_config.hpp"

namespace coflow::config {

const std::vector<std::string>& scheme_names() {
  static const std::vector<std::string> n{"serial-explicit", "parallel-explicit"};
  return n;
}

const char* scheme_name(Scheme s) {
  return s == Scheme::serial_explicit ? "serial-explicit" : "parallel-explicit";
}

Scheme scheme_from_name(const std::string& name) {
  if (name == "serial-explicit") return Scheme::serial_explicit;
  if (name == "parallel-explicit") return Scheme::parallel_explicit;
  throw std::invalid_argument(fmt::format("unknown coupling scheme '{}' (valid: {})", name, fmt::join(scheme_names(), ", ")));
}

bool Contract::provides_field(const std::string& name) const {
  return open || std::any_of(provides.begin(), provides.end(), [&](const Field& f) { return f.name == name; });
}

bool Contract::runs(Scheme s) const {
  return open || std::find(schemes.begin(), schemes.end(), s) != schemes.end();
}

namespace {

struct Party {
  const ComponentSchema* schema;
  const ComponentInfo* info;
  Contract contract;
  std::string label() const { return fmt::format("{}.{} {}", schema->section, schema->selector, info->variant); }
};

const char* where(Location l) { return l == Location::cell ? "cell" : "point"; }

// Variants of the other components (present or not) whose contract provides
// every one of `fields`: the fix to suggest.
std::vector<std::string> providers(const Config& cfg, const Catalog& catalog,
                                   const std::vector<std::string>& fields,
                                   const std::string& consumer_section) {
  std::vector<std::string> out;
  for (const auto& schema : catalog) {
    if (schema.section == consumer_section || !schema.contract) continue;
    std::vector<std::string> names;
    for (const auto& v : schema.variants) {
      if (v == "external") continue;
      const Contract c = schema.contract(cfg, v);
      if (std::all_of(fields.begin(), fields.end(),
                      [&](const std::string& f) { return c.provides_field(f); }))
        names.push_back(v);
    }
    if (!names.empty()) out.push_back(fmt::format("{}.{}: {}", schema.section, schema.selector, fmt::join(names, " or ")));
  }
  return out;
}

bool provided(const std::vector<Party>& run, const Party& me, const std::string& field) {
  for (const auto& other : run)
    if (&other != &me && other.contract.provides_field(field)) return true;
  return false;
}

// The needs of `me` that no other component meets, one message per key.
void check_needs(Reader& r, const Config& cfg, const Catalog& catalog, const std::vector<Party>& run, const Party& me) {
  std::vector<std::string> done;
  for (const auto& need : me.contract.needs) {
    if (std::find(done.begin(), done.end(), need.key) != done.end()) continue;
    std::vector<std::string> missing, fields, fix;
    std::string otherwise;
    for (const auto& n : me.contract.needs) {
      if (n.key != need.key || (!n.only_with.empty() && !cfg.has(n.only_with)) || provided(run, me, n.field.name))
        continue;
      missing.push_back(fmt::format("{} ({}, {})", n.field.name, where(n.field.location), n.field.units));
      fields.push_back(n.field.name);
      if (!n.otherwise.empty()) otherwise = n.otherwise;
    }
    done.push_back(need.key);
    if (missing.empty()) continue;
    // Variants that provide all of them; else, field by field, those that provide some.
    fix = providers(cfg, catalog, fields, me.schema->section);
    if (fix.empty())
      for (const auto& field : fields)
        for (const auto& p : providers(cfg, catalog, {field}, me.schema->section))
          if (std::find(fix.begin(), fix.end(), p) == fix.end()) fix.push_back(p);
    std::vector<std::string> others;
    for (const auto& other : run)
      if (&other != &me) others.push_back(other.label());
    r.fail(need.key,
           fmt::format("{} needs {}, which no other component of this run provides ({}); {}{}", me.label(),
                       fmt::join(missing, " and "),
                       others.empty() ? "it runs alone" : fmt::format("the run has {}", fmt::join(others, ", ")),
                       fix.empty() ? (otherwise.empty() ? "no variant provides it" : otherwise)
                                   : fmt::format("use {}", fmt::join(fix, "; ")),
                       fix.empty() || otherwise.empty() ? "" : ", " + otherwise));
  }
}

}  // namespace

void check_contracts(Reader& r, const Config& cfg, const Catalog& catalog) {
  std::vector<Party> run;
  for (const auto& schema : catalog) {
    if (!cfg.has(schema.section)) continue;
    const ComponentInfo& info = cfg.component(schema.section);
    Contract c;
    if (schema.contract && info.variant != "external") c = schema.contract(cfg, info.variant);
    else c.open = true;
    run.push_back({&schema, &info, std::move(c)});
  }
  for (const auto& p : run) {
    if (!p.contract.runs(cfg.coupling.scheme)) {
      std::vector<std::string> can;
      for (Scheme s : p.contract.schemes) can.push_back(scheme_name(s));
      r.fail("coupling.scheme", fmt::format("{} does not run the {} scheme (it runs: {}); use coupling.scheme: {}",
                                            p.label(), scheme_name(cfg.coupling.scheme), fmt::join(can, ", "),
                                            can.empty() ? "none" : can.front()));
    }
    check_needs(r, cfg, catalog, run, p);
  }
}

}  // namespace coflow::config
