// lbm-reference's part of the immersed boundary (immersed.method ibm): lbm's
// (fluid/lbm/immersed_boundary.cpp) on the serial grid. Between streaming and
// collision the same direct forcing (ibm/direct_forcing.hpp) drives the
// velocity u0 = (j + F/2) / rho of the pulled populations (F the body force
// and source) at the cells the markers' kernels reach to u, and the cell
// takes the force 2 rho (u - u0) in its collision (Guo: the seed's eq. 4.11
// with alpha2 / dt = 2); the standard formulation's loads take the density
// at the markers.
#include <cmath>

#include "fluid/lbm_reference/lbm_reference.hpp"
#include "immersed/ibm/params.hpp"

namespace coflow::fluid {

void LbmReference::set_markers(ibm::MarkerSet markers) {
  if (!ibm_) {
    const long nx = n_[0], ny = n_[1], nz = n_[2];
    auto index = [nx, ny, nz](const std::array<long, 3>& g) -> long {
      if (g[0] < 0 || g[0] >= nx || g[1] < 0 || g[1] >= ny || g[2] < 0 || g[2] >= nz) return -1;
      return (g[2] * ny + g[1]) * nx + g[0];
    };
    // The markers in m/s, the cells in lattice units.
    ibm_ = immersed::collocated_forcing(*cfg_, index, s_.units.velocity(), comm_);
    for (auto& a : ibm_u_) a.assign(static_cast<std::size_t>(nx * ny * nz), 0.0);
    ibm_force_.assign(static_cast<std::size_t>(3 * nx * ny * nz), 0.0);
    if (!s_.incompressible) ibm_density_.assign(static_cast<std::size_t>(nx * ny * nz), 1.0);
  }
  ibm_->set_markers(std::move(markers));
}

std::vector<double> LbmReference::take_body_loads() {
  return ibm_ ? ibm_->take_report() : std::vector<double>{};
}

void LbmReference::force_immersed(const std::function<double(long, int)>& pop) {
  const double t = static_cast<double>(steps_ + 1) * s_.units.dt;
  ibm_->prepare(t);
  const std::vector<long>& cells = ibm_->touched();
  std::vector<double> u0(3 * cells.size()), rho(cells.size()), f(static_cast<std::size_t>(Q_));
  for (std::size_t m = 0; m < cells.size(); ++m) {
    const long c = cells[m];
    double F[3], u[3], r;
    for (int q = 0; q < Q_; ++q) f[static_cast<std::size_t>(q)] = pop(c, q);
    force_at(c, F);
    fluid_velocity(f.data(), F, r, u);
    rho[m] = s_.incompressible ? 1.0 : r;
    for (std::size_t d = 0; d < 3; ++d) u0[3 * m + d] = u[d], ibm_u_[d][static_cast<std::size_t>(c)] = u[d];
    if (!ibm_density_.empty()) ibm_density_[static_cast<std::size_t>(c)] = rho[m];
  }
  ibm_->apply({ibm_u_[0].data(), ibm_u_[1].data(), ibm_u_[2].data()}, t, std::sqrt(max_u2_),
              2.0 * s_.units.force_density(), s_.units.dt, s_.incompressible ? nullptr : ibm_density_.data());
  std::fill(ibm_force_.begin(), ibm_force_.end(), 0.0);
  for (std::size_t m = 0; m < cells.size(); ++m)
    for (std::size_t d = 0; d < 3; ++d) {
      const auto c = static_cast<std::size_t>(cells[m]);
      ibm_force_[3 * c + d] = 2.0 * rho[m] * (ibm_u_[d][c] - u0[3 * m + d]);
    }
}

void LbmReference::total_force(long c, double F[3]) const {
  force_at(c, F);
  if (!ibm_force_.empty())
    for (int d = 0; d < 3; ++d) F[d] += ibm_force_[static_cast<std::size_t>(3 * c + d)];
}

void LbmReference::note_speed(const double* f, const double F[3]) {
  double rho, u[3];
  fluid_velocity(f, F, rho, u);
  const double uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
  step_u2_ = (uu != uu || step_u2_ != step_u2_) ? uu + step_u2_ : std::max(step_u2_, uu);
}

}  // namespace coflow::fluid
