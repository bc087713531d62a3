// lbm's part of the immersed boundary (immersed.method ibm): the direct
// forcing of ibm/direct_forcing.hpp on the cell centres, inside each step
// between streaming and collision (the core's hook). With Guo's forcing the
// collision's velocity is u = (j + F/2) / rho; the forcing drives u from its
// value without the boundary, u0, to u (the markers' velocities at the
// step's end interpolated back), and the cell's force is F = 2 rho (u - u0)
// (lattice units: the seed's eq. 4.11 with alpha2 / dt = 2, Guo's half
// force). Forces on the bodies in N: factor 2 x the force-density unit; in
// the standard formulation (rho varies) each marker's load takes the density
// interpolated there, so that the bodies take what the cells are given.
#include "fluid/lbm/lbm_solver.hpp"
#include "immersed/ibm/params.hpp"

namespace coflow::fluid {

void LbmSolver::set_markers(ibm::MarkerSet markers) {
  if (!ibm_) {
    const long nx = owned_.extent(0), ny = owned_.extent(1), nz = owned_.extent(2);
    auto index = [this, nx, ny, nz](const std::array<long, 3>& g) -> long {
      const long i = g[0] - owned_.lo[0], j = g[1] - owned_.lo[1], k = g[2] - owned_.lo[2];
      if (i < 0 || i >= nx || j < 0 || j >= ny || k < 0 || k >= nz) return -1;
      return (k * ny + j) * nx + i;
    };
    // The markers in m/s, the cells in lattice units.
    ibm_ = immersed::collocated_forcing(*cfg_, index, s_.units.velocity(), comm_);
    for (auto& a : ibm_u_) a.assign(static_cast<std::size_t>(nx * ny * nz), 0.0);
    if (!s_.incompressible) ibm_density_.assign(static_cast<std::size_t>(nx * ny * nz), 1.0);
    core_->set_hook([this] { force_immersed(); });
  }
  ibm_->set_markers(std::move(markers));
}

std::vector<double> LbmSolver::take_body_loads() {
  return ibm_ ? ibm_->take_report() : std::vector<double>{};
}

void LbmSolver::force_immersed() {
  const double t = static_cast<double>(steps_ + 1) * s_.units.dt;
  ibm_->prepare(t);
  const std::vector<long>& cells = ibm_->touched();
  const std::size_t n = cells.size();
  ibm_at_.resize(3 * n);
  ibm_rho_.resize(n);
  core_->streamed_velocity(cells, ibm_at_, ibm_rho_);
  for (std::size_t m = 0; m < n; ++m) {
    for (std::size_t d = 0; d < 3; ++d) ibm_u_[d][static_cast<std::size_t>(cells[m])] = ibm_at_[3 * m + d];
    if (!ibm_density_.empty()) ibm_density_[static_cast<std::size_t>(cells[m])] = ibm_rho_[m];
  }
  const double scale = std::sqrt(core_->max_u2());
  ibm_->apply({ibm_u_[0].data(), ibm_u_[1].data(), ibm_u_[2].data()}, t, scale,
              2.0 * s_.units.force_density(), s_.units.dt, s_.incompressible ? nullptr : ibm_density_.data());
  ibm_force_.resize(3 * n);
  for (std::size_t m = 0; m < n; ++m)
    for (std::size_t d = 0; d < 3; ++d)
      ibm_force_[3 * m + d] = 2.0 * ibm_rho_[m] * (ibm_u_[d][static_cast<std::size_t>(cells[m])] - ibm_at_[3 * m + d]);
  core_->set_cell_forces(cells, ibm_force_);
}

}  // namespace coflow::fluid
