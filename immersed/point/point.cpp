#include "immersed/point/point.hpp"
#include "immersed/point/stencil.hpp"

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
#include "particles/particles_interface.hpp"

namespace coflow::immersed {

using coupler::Index3;

void PointMethod::run(coupler::Session& s) {
  const auto& cfg = s.config();
  const auto& dom = cfg.domain;
  const double h = dom.spacing()[0], cell_volume = h * h * h;
  const coupler::Decomposition mine = s.decomposition();
  if (!s.has_partner("fluid") || !s.has_partner("particles"))
    throw std::runtime_error("immersed.method point couples a fluid and particles: both sections must be present");
  const double rho = cfg.resolved["fluid"]["density"].as<double>();
  const double mu = rho * cfg.resolved["fluid"]["viscosity"].as<double>();

  s.negotiate_window(0.0);
  const auto fluid_dec = s.decomposition_of("fluid", s.partner_ranks("fluid"));
  coupler::FieldExchange flow_in(s.partner("fluid"), coupler::FieldExchange::Role::receiver, mine, s.rank(),
                                 fluid_dec, coupler::FieldSpec{"flow", 5, coupler::Transfer::consistent, 2},
                                 protocol::kTagFlow);
  coupler::FieldExchange source_out(s.partner("fluid"), coupler::FieldExchange::Role::sender, mine, s.rank(),
                                    fluid_dec, coupler::FieldSpec{"source", 3, coupler::Transfer::conservative, 1},
                                    protocol::kTagSource);
  coupler::PointExchange states(s.partner("particles"), coupler::PointExchange::Role::destination, mine, dom.lower,
                                dom.spacing(), sizeof(protocol::ParticleRecord), sizeof(protocol::FluidAtParticle),
                                protocol::kTagParticles, 0);
  coupler::PointExchange impulses(s.partner("particles"), coupler::PointExchange::Role::destination, mine,
                                  dom.lower, dom.spacing(), sizeof(protocol::ParticleImpulse), sizeof(double),
                                  protocol::kTagImpulse, 0);
  log::info("point: trilinear interpolation and spreading, fluid rho {:.4g} kg/m^3, mu {:.4g} Pa s", rho, mu);

  output::Series series;
  if (s.rank() == 0)
    series = output::Series(s.output_dir() + "/series/immersed.csv",
                            {"time", "force_x", "force_y", "force_z", "torque_x", "torque_y", "torque_z",
                             "solid_volume"},
                            s.restart_window() > 0);

  std::vector<double> flow(flow_in.local_size()), source(source_out.local_size());
  std::vector<std::byte> records, results;
  std::vector<std::uint8_t> owned_flags;
  const int C = 5;  // u[3], k, epsilon
  auto value = [&](Index3 g, int comp) {
    for (int d = 0; d < 3; ++d)
      if (!dom.periodic[d]) g[d] = std::clamp(g[d], 0L, static_cast<long>(dom.cells[d]) - 1);
    return flow[static_cast<std::size_t>(flow_in.local_index(g)) * C + comp];
  };
  // Central differences (one-sided at non-periodic domain faces).
  auto derivative = [&](const Index3& g, int comp, int axis) {
    Index3 a = g, b = g;
    --a[axis];
    ++b[axis];
    long span = 2;
    if (!dom.periodic[axis]) {
      a[axis] = std::max(a[axis], 0L);
      b[axis] = std::min(b[axis], static_cast<long>(dom.cells[axis]) - 1);
      span = b[axis] - a[axis];
    }
    return span > 0 ? (value(b, comp) - value(a, comp)) / (static_cast<double>(span) * h) : 0.0;
  };
  auto vorticity = [&](const Index3& g, double* w) {
    w[0] = derivative(g, 2, 1) - derivative(g, 1, 2);
    w[1] = derivative(g, 0, 2) - derivative(g, 2, 0);
    w[2] = derivative(g, 1, 0) - derivative(g, 0, 1);
  };

  for (long w = s.restart_window() + 1; w <= s.windows(); ++w) {
    // 1. The fluid at the window's start.
    flow_in.receive(flow);
    // 2. Interpolated at the particles.
    states.receive(records, owned_flags);
    const std::size_t n = owned_flags.size();
    results.resize(n * sizeof(protocol::FluidAtParticle));
    for (std::size_t p = 0; p < n; ++p) {
      protocol::ParticleRecord r;
      std::memcpy(&r, records.data() + p * sizeof r, sizeof r);
      const Stencil st = stencil(r.x, dom, h);
      protocol::FluidAtParticle f{};
      for (int c = 0; c < 8; ++c) {
        double om[3];
        vorticity(st.cell[c], om);
        for (int d = 0; d < 3; ++d) {
          f.u[d] += st.weight[c] * value(st.cell[c], d);
          f.vorticity[d] += st.weight[c] * om[d];
        }
        f.k += st.weight[c] * value(st.cell[c], 3);
        f.epsilon += st.weight[c] * value(st.cell[c], 4);
      }
      f.rho = rho;
      f.mu = mu;
      std::memcpy(results.data() + p * sizeof f, &f, sizeof f);
    }
    states.send_results(results);
    // 3. The impulses of the window, spread as a force density.
    impulses.receive(records, owned_flags);
    const std::size_t m = owned_flags.size();
    source_out.flush();  // the previous window's message may still read `source`
    std::fill(source.begin(), source.end(), 0.0);
    double total[3] = {0, 0, 0};
    for (std::size_t p = 0; p < m; ++p) {
      protocol::ParticleImpulse r;
      std::memcpy(&r, records.data() + p * sizeof r, sizeof r);
      const Stencil st = stencil(r.x, dom, h);
      for (int d = 0; d < 3; ++d) total[d] += r.impulse[d] / s.window();
      for (int c = 0; c < 8; ++c) {
        const long l = source_out.local_index(st.cell[c]);
        for (int d = 0; d < 3; ++d)
          source[static_cast<std::size_t>(l) * 3 + d] -= st.weight[c] * r.impulse[d] / (s.window() * cell_volume);
      }
    }
    // 4. To the fluid, once it is known to be finite.
    coupler::check_finite(s.comm(),
                          {"immersed (point)", "cell value", "a particle's impulse is not finite: see the particles' log"},
                          w, w * s.window(), {{"momentum source", source}}, 3);
    source_out.send(source);

    if (s.series_due(w)) {
      double sum[3];
      MPI_Reduce(total, sum, 3, MPI_DOUBLE, MPI_SUM, 0, s.comm());
      const double row[] = {w * s.window(), sum[0], sum[1], sum[2], 0.0, 0.0, 0.0, 0.0};
      if (s.rank() == 0) series.row(row);
    }
    coupler::trace().steps = w;
    s.checkpoint(w, [](const std::string&) {});  // no state of its own
    s.window_done(w);
  }
  source_out.flush();
}

}  // namespace coflow::immersed
