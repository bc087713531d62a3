// What a point-particle checkpoint holds beyond the particle states of
// dem::save_state: the inlets' owed mass and serials, the next particle id, and
// each particle's turbulent fluctuation u' (dispersion), in dpm.csv:
//   time,<the variant's own clock>   (accumulated step by step: the driver's
//                                    window time may differ in the last bit)
//   next_id,<id>
//   inlet,<k>,<owed>,<serial>,<tries>   (checkpoints before 2026-12-04: no tries, read as 0)
//   uprime,<id>,<ux>,<uy>,<uz>,<started 0|1>
// Numbers are written with 17 significant digits (bit-identical restart).
#pragma once

#include <fmt/format.h>

#include <cstdint>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "coflow/output.hpp"
#include "coflow/run_config.hpp"
#include "particles/dpm/injection.hpp"

namespace coflow::particles::dpm {

struct Fluctuation {
  V3 u = V3::Zero();
  bool started = false;
};

inline void save_extra(const std::string& dir, double time, std::int64_t next_id, const std::vector<Inlet>& inlets,
                       const std::map<std::int64_t, Fluctuation>& uprime) {
  std::string out = fmt::format("time,{:.17g}\n", time);
  out += fmt::format("next_id,{}\n", next_id);
  for (std::size_t k = 0; k < inlets.size(); ++k)
    out += fmt::format("inlet,{},{:.17g},{},{}\n", k, inlets[k].owed, inlets[k].serial, inlets[k].tries);
  for (const auto& [id, f] : uprime)
    out +=
        fmt::format("uprime,{},{:.17g},{:.17g},{:.17g},{}\n", id, f.u[0], f.u[1], f.u[2], f.started ? 1 : 0);
  output::atomic_write(dir + "/dpm.csv", out);  // judged after the close (a full disk shows there)
}

// Reads dpm.csv back (absent in checkpoints of runs without it: nothing changes).
inline void load_extra(const std::string& dir, double& time, std::int64_t& next_id, std::vector<Inlet>& inlets,
                       std::map<std::int64_t, Fluctuation>& uprime) {
  std::ifstream in(dir + "/dpm.csv");
  if (!in) return;
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    std::stringstream ss(line);
    std::string kind, field;
    std::getline(ss, kind, ',');
    std::vector<std::string> f;
    while (std::getline(ss, field, ',')) f.push_back(field);
    try {
      if (kind == "time" && f.size() == 1) {
        time = config::to_number(f[0]);
      } else if (kind == "next_id" && f.size() == 1) {
        next_id = std::stoll(f[0]);
      } else if (kind == "inlet" && (f.size() == 3 || f.size() == 4)) {
        const auto k = static_cast<std::size_t>(std::stoul(f[0]));
        if (k >= inlets.size()) throw std::runtime_error("inlet index beyond particles.injection");
        inlets[k].owed = config::to_number(f[1]);
        inlets[k].serial = std::stoll(f[2]);
        inlets[k].tries = f.size() == 4 ? std::stoll(f[3]) : 0;
      } else if (kind == "uprime" && f.size() == 5) {
        uprime[std::stoll(f[0])] = {
            V3(config::to_number(f[1]), config::to_number(f[2]), config::to_number(f[3])), f[4] == "1"};
      } else if (!line.empty()) {
        throw std::runtime_error("unknown record");
      }
    } catch (const std::exception& e) {
      throw std::runtime_error(fmt::format("{}/dpm.csv:{}: {}", dir, n, e.what()));
    }
  }
}

}  // namespace coflow::particles::dpm
