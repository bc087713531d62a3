#include "immersed/point/point.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numbers>
#include <stdexcept>

#include "coflow/exchange.hpp"
#include "coflow/finite.hpp"
#include "coflow/log.hpp"
#include "coflow/output.hpp"
#include "coflow/protocol.hpp"
#include "coflow/session.hpp"
#include "coflow/trace.hpp"
#include "coflow/window_loop.hpp"
#include "immersed/order_by_id.hpp"
#include "immersed/point/stencil.hpp"
#include "immersed/series.hpp"
#include "particles/particles_interface.hpp"

namespace coflow::immersed {

using coupler::Index3;

namespace {

// One window of the point method: 1. the fluid at the window's start arrives;
// 2. it is interpolated at the particles, with its vorticity, and goes back to
// them; 3. after their sub-steps the particles' impulses arrive and are spread
// as a force density (seed 003 eq. 3.43); 4. that goes to the fluid, once it is
// known to be finite. Each rank spreads into its own cells only, the impulses
// of the particles whose stencil reaches them (the impulses come with ghost
// copies one cell wide), by particle id: a cell's source is the same sum, bit
// for bit, for any number of immersed and particle ranks.
class PointWindows final : public coupler::WindowParts {
 public:
  PointWindows(coupler::Session& s, double rho, double mu, bool two_way, const std::string& series);
  void before_step(long) override;   // 1, 2
  void step(long) override {}        // the particles and the fluid step
  void after_step(long w) override;  // 3, 4
  void output(long w) override;
  void save(const std::string&) override {}  // no state of its own
  void finish() override { source_out_.flush(); }

 private:
  double value(Index3 g, int comp) const;
  double derivative(const Index3& g, int comp, int axis) const;
  void vorticity(const Index3& g, double* w) const;
  protocol::FluidAtParticle sample(const protocol::ParticleRecord& r) const;
  void check_impulses(long w, std::size_t m);

  static constexpr int C = 5;  // u[3], k, epsilon
  coupler::Session& s_;
  const config::DomainParams& dom_;
  config::Vec3 h_;  // the cells' sides
  double rho_, mu_;
  bool two_way_;  // the impulses are spread into the fluid's momentum source
  coupler::FieldExchange flow_in_, source_out_;
  coupler::PointExchange states_, impulses_;
  std::vector<double> flow_, source_;
  std::vector<std::byte> records_, results_;
  std::vector<std::uint8_t> owned_flags_;
  std::vector<protocol::ParticleImpulse> rec_;  // the window's impulses, unpacked
  std::vector<std::size_t> order_;              // rec_ by particle id
  coupler::Decomposition dec_;
  coupler::Box owned_;
  double total_[3] = {0, 0, 0};
  ImmersedSeries series_;
};

PointWindows::PointWindows(coupler::Session& s, double rho, double mu, bool two_way,
                           const std::string& series)
    : s_(s),
      dom_(s.config().domain),
      h_(dom_.spacing()),
      rho_(rho),
      mu_(mu),
      two_way_(two_way),
      flow_in_(s.partner("fluid"), coupler::FieldExchange::Role::receiver, s.decomposition(), s.rank(),
               s.decomposition_of("fluid", s.partner_ranks("fluid")),
               coupler::FieldSpec{"flow", 5, coupler::Transfer::consistent, 2}, protocol::kTagFlow),
      source_out_(s.partner("fluid"), coupler::FieldExchange::Role::sender, s.decomposition(), s.rank(),
                  s.decomposition_of("fluid", s.partner_ranks("fluid")),
                  coupler::FieldSpec{"source", 3, coupler::Transfer::conservative, 1}, protocol::kTagSource),
      states_(s.partner("particles"), coupler::PointExchange::Role::destination, s.decomposition(),
              dom_.lower, dom_.spacing(), sizeof(protocol::ParticleRecord), sizeof(protocol::FluidAtParticle),
              protocol::kTagParticles, 0),
      impulses_(s.partner("particles"), coupler::PointExchange::Role::destination, s.decomposition(),
                dom_.lower, dom_.spacing(), sizeof(protocol::ParticleImpulse), sizeof(double),
                protocol::kTagImpulse, protocol::kImpulseGhost),
      flow_(flow_in_.local_size()),
      source_(source_out_.local_size()),
      dec_(s.decomposition()),
      owned_(dec_.block(s.rank())),
      series_(s, series) {
  log::info("point: trilinear interpolation and spreading, fluid rho {:.4g} kg/m^3, mu {:.4g} Pa s", rho, mu);
}

double PointWindows::value(Index3 g, int comp) const {
  for (int d = 0; d < 3; ++d)
    if (!dom_.periodic[d] || dom_.cells[d] == 1)
      g[d] = std::clamp(g[d], 0L, static_cast<long>(dom_.cells[d]) - 1);
  return flow_[static_cast<std::size_t>(flow_in_.local_index(g)) * C + comp];
}

// Central differences (one-sided at non-periodic domain faces).
double PointWindows::derivative(const Index3& g, int comp, int axis) const {
  Index3 a = g, b = g;
  --a[axis];
  ++b[axis];
  long span = 2;
  if (!dom_.periodic[axis]) {
    a[axis] = std::max(a[axis], 0L);
    b[axis] = std::min(b[axis], static_cast<long>(dom_.cells[axis]) - 1);
    span = b[axis] - a[axis];
  }
  if (dom_.cells[axis] == 1) return 0.0;  // nothing varies along an axis of one cell
  return span > 0 ? (value(b, comp) - value(a, comp)) / (static_cast<double>(span) * h_[axis]) : 0.0;
}

void PointWindows::vorticity(const Index3& g, double* w) const {
  w[0] = derivative(g, 2, 1) - derivative(g, 1, 2);
  w[1] = derivative(g, 0, 2) - derivative(g, 2, 0);
  w[2] = derivative(g, 1, 0) - derivative(g, 0, 1);
}

// The velocity and vorticity are linear up to the faces (extrapolated in the
// half cell next to a face); k and epsilon take the clamped stencil, whose
// weights are never negative, so that they stay positive.
protocol::FluidAtParticle PointWindows::sample(const protocol::ParticleRecord& r) const {
  const Stencil st = stencil(r.x, dom_, h_, true), kept = stencil(r.x, dom_, h_);
  protocol::FluidAtParticle f{};
  for (int c = 0; c < 8; ++c) {
    double om[3];
    vorticity(st.cell[c], om);
    for (int d = 0; d < 3; ++d) {
      f.u[d] += st.weight[c] * value(st.cell[c], d);
      f.vorticity[d] += st.weight[c] * om[d];
    }
    f.k += kept.weight[c] * value(kept.cell[c], 3);
    f.epsilon += kept.weight[c] * value(kept.cell[c], 4);
  }
  f.rho = rho_;
  f.mu = mu_;
  return f;
}

void PointWindows::before_step(long) {
  flow_in_.receive(flow_);
  states_.receive(records_, owned_flags_);
  const std::size_t n = owned_flags_.size();
  results_.resize(n * sizeof(protocol::FluidAtParticle));
  for (std::size_t p = 0; p < n; ++p) {
    protocol::ParticleRecord r;
    std::memcpy(&r, records_.data() + p * sizeof r, sizeof r);
    const protocol::FluidAtParticle f = sample(r);
    std::memcpy(results_.data() + p * sizeof f, &f, sizeof f);
  }
  states_.send_results(results_);
}

// The m impulses received: each finite (one-way runs too, whose series
// would take a NaN), collectively, naming the particle. The positions came
// checked (PointExchange::send), so the source spread from them is finite.
void PointWindows::check_impulses(long w, std::size_t m) {
  std::vector<double> impulse(3 * m);
  std::vector<std::int64_t> ids(m);
  for (std::size_t p = 0; p < m; ++p) {
    protocol::ParticleImpulse r;
    std::memcpy(&r, records_.data() + p * sizeof r, sizeof r);
    std::copy(r.impulse, r.impulse + 3, impulse.begin() + 3 * static_cast<long>(p));
    ids[p] = r.id;
  }
  coupler::check_finite(s_.comm(),
                        {"immersed (point)", "particle", "its impulse is not finite: see the particles' log"},
                        w, w * s_.window(), {{"impulse", impulse}}, 3, ids);
}

void PointWindows::after_step(long w) {
  impulses_.receive(records_, owned_flags_);
  const std::size_t m = owned_flags_.size();
  const double cell_volume = h_[0] * h_[1] * h_[2];
  source_out_.flush();  // the previous window's message may still read source_
  std::fill(source_.begin(), source_.end(), 0.0);
  std::fill(total_, total_ + 3, 0.0);
  check_impulses(w, m);
  rec_.resize(m);
  if (m > 0) std::memcpy(rec_.data(), records_.data(), m * sizeof(protocol::ParticleImpulse));
  order_by_id(m, order_, [this](std::size_t p) { return rec_[p].id; });
  for (const std::size_t p : order_) {
    const protocol::ParticleImpulse& r = rec_[p];
    if (owned_flags_[p])
      for (int d = 0; d < 3; ++d) total_[d] += r.impulse[d] / s_.window();
    if (!two_way_) continue;  // one-way: the fluid gets no source
    const Stencil st = stencil(r.x, dom_, h_);
    for (int c = 0; c < 8; ++c) {
      const Index3 g = dec_.wrap(st.cell[c]);
      if (!owned_.contains(g)) continue;  // its owner spreads it, from its own copy
      const long l = source_out_.local_index(g);
      for (int d = 0; d < 3; ++d)
        source_[static_cast<std::size_t>(l) * 3 + d] -= st.weight[c] * r.impulse[d] / (s_.window() * cell_volume);
    }
  }
  source_out_.send(source_);
  coupler::trace().steps = w;
}

void PointWindows::output(long w) {
  const double total[7] = {total_[0], total_[1], total_[2], 0.0, 0.0, 0.0, 0.0};  // no torque, no solid volume
  series_.write(w, total);
}

}  // namespace

std::unique_ptr<coupler::WindowParts> make_point_windows(coupler::Session& s, const std::string& series) {
  const auto& cfg = s.config();
  const double rho = cfg.resolved["fluid"]["density"].as<double>();
  const double mu = rho * cfg.resolved["fluid"]["viscosity"].as<double>();
  // One-way when asked, or when the fluid takes no momentum source (its
  // contract: analytic is a prescribed flow).
  const std::string fluid = cfg.component("fluid").variant;
  const bool asked_one_way = config::resolved_text(cfg, {"particles", "coupling"}) == "one-way";
  const bool fluid_takes = fluid != "analytic";
  const bool two_way = !asked_one_way && fluid_takes;
  log::info("point: {} coupling{}", two_way ? "two-way" : "one-way",
            two_way ? " (the particles' momentum source acts on the fluid, seed 003 eq. 3.43)"
                    : asked_one_way ? " (particles.coupling: one-way): the fluid does not feel the particles"
                                    : fmt::format(" (fluid.solver {} takes no momentum source): the fluid does not "
                                                  "feel the particles",
                                                  fluid));
  return std::make_unique<PointWindows>(s, rho, mu, two_way, series);
}

void PointMethod::run(coupler::Session& s) {
  if (!s.has_partner("fluid") || !s.has_partner("particles"))
    throw std::runtime_error(
        "immersed.method point couples a fluid and particles: both sections must be present");
  s.negotiate_window(0.0);
  const auto windows = make_point_windows(s, "immersed");
  coupler::run_windows(s, *windows);
}

}  // namespace coflow::immersed
