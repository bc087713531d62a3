// Variants, in two halves that link apart:
// - VariantSchema: a variant's name, summary and parameter keys (its YAML
//   subsection). A component's schema library lists them; the launcher and
//   the docs generator link the schema libraries only.
// - Registry: name -> factory of the solver class, filled by one explicit
//   function per component (no macros, no self-registering statics); linked by
//   the component executable.
#pragma once

#include <algorithm>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "coflow/config.hpp"
#include "coflow/run_config.hpp"

namespace coflow {

struct VariantSchema {
  std::string name;
  std::string summary;         // one line for `coflow variants`
  std::string params_section;  // "" when the variant has no subsection
  // Visit the variant's Params (defaults), for reading or describing; with a
  // configuration, also run the Params' checks against the rest of it.
  std::function<void(config::Visitor&, const config::Config*)> visit;
};

// A variant whose Params declares `void visit(config::Visitor&)` and
// optionally `void check(config::Visitor&, const config::Config&) const`.
template <class Params>
VariantSchema variant_schema(std::string name, std::string summary, std::string params_section = "") {
  VariantSchema s{std::move(name), std::move(summary), std::move(params_section), {}};
  s.visit = [](config::Visitor& v, const config::Config* cfg) {
    Params p;
    p.visit(v);
    if constexpr (requires { p.check(v, *cfg); })
      if (cfg && v.reading()) p.check(v, *cfg);
  };
  return s;
}

template <class List>
const VariantSchema& find_variant(const List& list, const std::string& name) {
  auto it = std::find_if(list.begin(), list.end(), [&](const VariantSchema& e) { return e.name == name; });
  if (it == list.end()) throw std::invalid_argument(fmt::format("unknown variant '{}'", name));
  return *it;
}

template <class List>
bool has_variant(const List& list, const std::string& name) {
  return std::any_of(list.begin(), list.end(), [&](const VariantSchema& e) { return e.name == name; });
}

// The parts of a component's schema every component fills alike: its section,
// selector key, variant names (plus "external") and doc.
inline config::ComponentSchema component_schema(std::string section, std::string selector,
                                                const std::vector<VariantSchema>& variants, std::string doc) {
  config::ComponentSchema s;
  s.section = std::move(section);
  s.selector = std::move(selector);
  for (const auto& e : variants) s.variants.push_back(e.name);
  s.variants.push_back("external");
  s.doc = std::move(doc);
  return s;
}

// Interface::Setup is what every variant of a family is constructed from. A
// variant T provides `T::Params` (the struct its VariantSchema reads) and
// `T(const Interface::Setup&, const T::Params&)`.
template <class Interface>
class Registry {
 public:
  using Setup = typename Interface::Setup;
  struct Entry {
    std::string name;
    // Read the Params from a visitor over the subsection and build the variant.
    std::function<std::unique_ptr<Interface>(const Setup&, config::Visitor&)> create;
  };

  template <class T>
  void add(std::string name) {
    add<typename T::Params>(std::move(name), [](const Setup& setup, const typename T::Params& p) -> std::unique_ptr<Interface> {
      return std::make_unique<T>(setup, p);
    });
  }

  // A variant whose factory picks the class from its Params.
  template <class Params>
  void add(std::string name, std::function<std::unique_ptr<Interface>(const Setup&, const Params&)> make) {
    Entry e;
    e.name = std::move(name);
    e.create = [make](const Setup& setup, config::Visitor& v) -> std::unique_ptr<Interface> {
      Params p;
      p.visit(v);
      return make(setup, p);
    };
    entries_.push_back(std::move(e));
  }

  const Entry& at(const std::string& name) const {
    auto it = std::find_if(entries_.begin(), entries_.end(), [&](const Entry& e) { return e.name == name; });
    if (it == entries_.end())
      throw std::invalid_argument(fmt::format("unknown variant '{}' (valid: {})", name, fmt::join(names(), ", ")));
    return *it;
  }
  std::vector<std::string> names() const {
    std::vector<std::string> n;
    for (const auto& e : entries_) n.push_back(e.name);
    return n;
  }
  const std::vector<Entry>& entries() const { return entries_; }

 private:
  std::vector<Entry> entries_;
};

}  // namespace coflow
