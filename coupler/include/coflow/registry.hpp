// A plain registry: name -> factory, filled by one explicit function per
// component (no macros, no self-registering statics).
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

// Interface::Setup is what every variant of a family is constructed from.
// A variant T provides:
//   struct T::Params { void visit(config::Visitor&); };   (its YAML subsection)
//   static constexpr const char* T::params_section;      ("" when none)
//   static constexpr const char* T::summary;             (one line for `coflow variants`)
//   T(const Interface::Setup&, const T::Params&)
template <class Interface>
class Registry {
 public:
  using Setup = typename Interface::Setup;
  struct Entry {
    std::string name;
    std::string summary;
    std::string params_section;
    // Visit the variant's Params (defaults), for reading or describing; with a
    // configuration, also run the Params' checks against the rest of it.
    std::function<void(config::Visitor&, const config::Config*)> visit;
    std::function<void(config::Visitor&)> describe;
    // Read the Params from a visitor over the subsection and build the variant.
    std::function<std::unique_ptr<Interface>(const Setup&, config::Visitor&)> create;
  };

  template <class T>
  void add(std::string name) {
    Entry e;
    e.name = std::move(name);
    e.summary = T::summary;
    e.params_section = T::params_section;
    e.visit = [](config::Visitor& v, const config::Config* cfg) {
      typename T::Params p;
      p.visit(v);
      if constexpr (requires { p.check(v, *cfg); })
        if (cfg && v.reading()) p.check(v, *cfg);
    };
    e.describe = [](config::Visitor& v) {
      typename T::Params p;
      p.visit(v);
    };
    e.create = [](const Setup& setup, config::Visitor& v) -> std::unique_ptr<Interface> {
      typename T::Params p;
      p.visit(v);
      return std::make_unique<T>(setup, p);
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
