// fv's part of the immersed boundary (immersed.method ibm): the multi-direct
// forcing of ibm/direct_forcing.hpp on the staggered velocity, between the
// momentum predictor and the projection (seed 003 eqs. 4.7-4.11: u* from eq.
// 4.7, then u^{n+1} = u* + f dt / (alpha2 rho), alpha2 the SBDF2 / CNAB2
// coefficient of u^{n+1}). The projection that follows removes the
// divergence the forcing made; the slip it leaves is O(dt).
//
// That force never meets the step's implicit diffusion: a steady state
// balances nu lap u against f - nu dt/alpha2 lap f, whose second term grows
// with nu dt / h^2 (Couette's torque 27 % low at 7.3). Stage in_predictor
// finds the force on the explicit estimate of u* (the implicit diffusion
// taken at u^n), u~ = dt/alpha2 (rhs + theta nu lap u^n), and adds
// alpha2 (u~_forced - u~) / dt to the predictor's rows: the force enters the
// balance it corrects, and where u^{n+1} = u^n, u~ = u^{n+1} - that change,
// so a steady state has the markers' velocities whatever the step (the
// placement of Uhlmann 2005's force, with the viscous term implicit):
// force_in_predictor, in momentum.cpp beside the rows it shares.
#include "fluid/fv/fv_solver.hpp"
#include "immersed/ibm/params.hpp"

namespace coflow::fluid {

void FvSolver::set_markers(ibm::MarkerSet markers) {
  if (!ibm_) {
    // u_c's unknowns on this rank: the owned faces that are not the domain's.
    auto index = [this](int c, const std::array<long, 3>& g) -> long {
      long at[3];
      for (int d = 0; d < 3; ++d) {
        at[d] = g[static_cast<std::size_t>(d)] - blk_.owned.lo[d];
        if (at[d] < 0 || at[d] >= blk_.extent[d]) return -1;
      }
      return is_boundary_face(c, at[c]) ? -1 : blk_.idx(at[0], at[1], at[2]);
    };
    ibm_ = immersed::staggered_forcing(cfg_, periodic_, index, comm_);
    ibm_in_predictor_ = immersed::read_ibm_params(cfg_).stage == "in_predictor";
  }
  if (turbulent_) set_body_wall_distance(markers);
  markers_speed_ = fv::marker_speeds(markers);
  ibm_->set_markers(std::move(markers));
}

std::vector<double> FvSolver::take_body_loads() { return ibm_ ? ibm_->take_report() : std::vector<double>{}; }

// After the momentum predictor: u* forced toward the markers' velocities at
// the new time. The force density is alpha2 rho du / dt (eq. 4.8).
void FvSolver::force_immersed(const fv::Imex& s, double dt) {
  if (!ibm_ || ibm_->empty()) return;
  const double start = MPI_Wtime();
  std::array<double*, 3> u{nullptr, nullptr, nullptr};
  for (int c = 0; c < dims_; ++c) u[static_cast<std::size_t>(c)] = ustar_[static_cast<std::size_t>(c)].data();
  ibm_->apply(u, next_time_, velocity_scale_, s.a0 * rho_ / dt, dt);
  ibm_seconds_ += MPI_Wtime() - start;
}

}  // namespace coflow::fluid
