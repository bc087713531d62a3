// fv-reference's part of the immersed boundary: fv's (fluid/fv/
// immersed_boundary.cpp) on the serial grid, the same direct forcing
// (ibm/direct_forcing.hpp) on u* at the end of the momentum step, before its
// ghosts are filled, or on the explicit estimate of u* in the momentum step
// (immersed.ibm.stage in_predictor).
#include "fluid/fv/turbulence/wall_distance.hpp"
#include "fluid/fv_reference/fv_reference.hpp"
#include "immersed/ibm/params.hpp"

namespace coflow::fluid {

void FvReference::set_markers(ibm::MarkerSet markers) {
  if (!ibm_) {
    auto index = [this](int c, const std::array<long, 3>& g) -> long {
      for (int d = 0; d < 3; ++d)
        if (g[static_cast<std::size_t>(d)] < 0 || g[static_cast<std::size_t>(d)] >= n_[d]) return -1;
      return unknown(c, g[static_cast<std::size_t>(c)]) ? at(g[0], g[1], g[2]) : -1;
    };
    const std::array<bool, 3> periodic{sides_[0].kind == Kind::periodic, sides_[2].kind == Kind::periodic,
                                       sides_[4].kind == Kind::periodic};
    ibm_ = immersed::staggered_forcing(cfg_, periodic, index, comm_);
    ibm_stage_ = immersed::read_ibm_params(cfg_).stage;
  }
  if (turbulent_) {  // the bodies are walls for k-epsilon too: fv's distance (turbulence/wall_distance.hpp)
    const fv::BodyDistance body(markers, fv::BodyDistance::grid_of(cfg_));
    double floor = h_[0];  // as fv: no closer than a quarter of the smallest spacing (y = 0: infinite epsilon)
    for (int a = 1; a < dims_; ++a) floor = std::min(floor, h_[a]);
    floor *= 0.25;
    for (long k = -g_[2]; k < n_[2] + g_[2]; ++k)
      for (long j = -g_[1]; j < n_[1] + g_[1]; ++j)
        for (long i = -g_[0]; i < n_[0] + g_[0]; ++i) {
          const long x[3] = {i, j, k};
          std::array<double, 3> c{0, 0, 0};
          for (int a = 0; a < dims_; ++a)
            c[static_cast<std::size_t>(a)] =
                cfg_.domain.lower[static_cast<std::size_t>(a)] + (x[a] + 0.5) * h_[a];
          const auto n = static_cast<std::size_t>(at(x));
          wall_y_[n] = std::min(box_wall_y_[n], std::max(body(c), floor));
        }
    eddy_viscosity();  // nu_t of the two-layer model near the bodies
  }
  markers_speed_ = fv::marker_speeds(markers);
  ibm_->set_markers(std::move(markers));
}

std::vector<double> FvReference::take_body_loads() {
  return ibm_ ? ibm_->take_report() : std::vector<double>{};
}

void FvReference::force_immersed(Faces& star, const fv::Imex& s, double dt) {
  if (!ibm_ || ibm_->empty()) return;
  std::array<double*, 3> u{nullptr, nullptr, nullptr};
  for (int c = 0; c < dims_; ++c) u[static_cast<std::size_t>(c)] = star[static_cast<std::size_t>(c)].data();
  ibm_->apply(u, next_time_, velocity_scale_, s.a0 * rho_ / dt, dt);
}

}  // namespace coflow::fluid
