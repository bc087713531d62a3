// The per-phase columns of series/fluid.csv for two fluids (colour gradient):
// each colour's mass, the red saturation of the pore space and each phase's
// flow rate along each axis. Shared by lbm and lbm-reference.
#pragma once

#include <mpi.h>

#include <algorithm>
#include <array>
#include <span>
#include <vector>

#include "coflow/output.hpp"
#include "fluid/lbm/units.hpp"

namespace coflow::fluid::lbm {

inline std::vector<output::Series::Column> phase_columns() {
  return {{"mass_red", "kg"},       {"mass_blue", "kg"},      {"saturation_red", "1"},
          {"flow_red_x", "m^3/s"},  {"flow_red_y", "m^3/s"},  {"flow_red_z", "m^3/s"},
          {"flow_blue_x", "m^3/s"}, {"flow_blue_y", "m^3/s"}, {"flow_blue_z", "m^3/s"}};
}

// Owned cells, lattice units: density rho, velocity u (3 per cell), colour
// fraction phase = (rho_r - rho_b) / rho, solid mask (nonzero: solid, left
// out), and the psm grains' solid fraction eps of each cell as the two-fluid
// collision takes it (empty: no grains; 0 next to open faces, where the
// collision leaves grains out). A cell's pore volume is (1 - eps) dV: the saturation is the red
// share of the pore volume, and a phase's flow rate along an axis its volume
// flux averaged over the domain's length on that axis, Q = (1/L) sum u psi (1
// - eps) dV with psi = (1 +/- phase)/2: in steady incompressible flow, the
// rate through every section. The masses are of all the populations (a
// grain's cells keep theirs). Collective over comm.
inline std::vector<double> phase_values(const Units& units, const std::array<long, 3>& cells,
                                        std::span<const double> rho, std::span<const double> u,
                                        std::span<const double> phase, std::span<const double> solid,
                                        std::span<const double> grain, MPI_Comm comm) {
  std::array<double, 10> s{};  // mass r, mass b, red pore volume, pore volume, flux r (3), flux b (3)
  for (std::size_t c = 0; c < rho.size(); ++c) {
    if (solid[c] != 0.0) continue;
    const double red = 0.5 * (1.0 + phase[c]), blue = 0.5 * (1.0 - phase[c]);
    const double pore = grain.empty() ? 1.0 : 1.0 - std::min(1.0, grain[c]);
    s[0] += rho[c] * red;
    s[1] += rho[c] * blue;
    s[2] += red * pore;
    s[3] += pore;
    for (int d = 0; d < 3; ++d) {
      s[4 + d] += u[3 * c + d] * red * pore;
      s[7 + d] += u[3 * c + d] * blue * pore;
    }
  }
  std::array<double, 10> g{};
  MPI_Allreduce(s.data(), g.data(), 10, MPI_DOUBLE, MPI_SUM, comm);
  const double vol = units.dx * units.dx * units.dx;
  std::vector<double> out{g[0] * units.rho * vol, g[1] * units.rho * vol, g[3] > 0 ? g[2] / g[3] : 0.0};
  for (int k = 0; k < 2; ++k)
    for (int d = 0; d < 3; ++d)
      out.push_back(g[4 + 3 * k + d] * units.velocity() * vol / (static_cast<double>(cells[d]) * units.dx));
  return out;
}

}  // namespace coflow::fluid::lbm
