#include "fluid/fv/amr/composite_turbulence.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "fluid/fv/scheme.hpp"
#include "fluid/fv/turbulence/closure.hpp"

namespace coflow::fluid::fv::amr {
// One link of a cell, per unit volume: advection moves q_c by
// -dt flux (q_face - q_c) (explicit; flux the outward volume flux over the
// cell's volume), diffusion is the implicit system's coupling
// -diffusion (q'_across - q'_c); q_across is the cell across the face or,
// where slot is -1, the boundary's value.
struct CompositeTurbulence::Link {
  long slot = -1, id = -1;   // the cell across: slot (fields with ghosts) and global id
  std::size_t face = 0;      // the sub-face's number among the cell's (upstream_)
  int side = 1;              // the face's outward normal along its axis
  double velocity = 0.0;     // the face-normal velocity along +axis (m/s)
  double flux = 0.0;         // outward volume flux over the cell's volume, 1/s
  double diffusion[2] = {};  // k, epsilon: (nu + nu_t / sigma) A / (V distance), 1/s
  double boundary[2] = {};   // k and epsilon beyond the face where slot is -1
};

// Each local cell's links (see Link) from the flow's faces and last face
// velocities, nu_t per slot. Across a face between cells the distance is
// the centres' (h, or 3/2 of the finer's across levels), nu_t the two
// cells' mean; a wall holds k = 0 half a cell away (nu_t = 0 there) and no
// flux of epsilon; an inlet the inlet's values half a cell away; outlets
// and symmetry faces nothing (outflow carries the cell's own value).
std::vector<std::vector<CompositeTurbulence::Link>> CompositeTurbulence::links(
    const std::vector<double>& nut) const {
  const auto& faces = flow_.faces();
  const double inv_sigma[2] = {1.0 / params_.constants.sigma_k, 1.0 / params_.constants.sigma_epsilon};
  std::vector<std::vector<Link>> out(faces.size());
  for (std::size_t c = 0; c < faces.size(); ++c) {
    const double h = flow_.spacing(c);
    for (std::size_t s = 0; s < faces[c].size(); ++s) {
      const auto& f = faces[c][s];
      Link l;
      l.face = s;
      l.side = f.side;
      l.velocity = flow_.normal_velocity(c, s);
      l.flux = f.side * l.velocity * f.fraction / h;
      if (!f.wall) {
        l.slot = f.across_slot;
        l.id = f.across;
        const double distance = f.across_level == 0 ? h : f.across_level < 0 ? 1.5 * h : 0.75 * h;
        const double nut_face = 0.5 * (nut[c] + nut[static_cast<std::size_t>(f.across_slot)]);
        for (int q = 0; q < 2; ++q)
          l.diffusion[q] = (nu_ + nut_face * inv_sigma[q]) * f.fraction / (h * distance);
      } else {
        const auto kind = flow_.boundary(2 * f.axis + (f.side > 0));
        if (kind == CompositeFlow::Boundary::wall) {
          l.diffusion[0] = 2.0 * nu_ / (h * h);  // k = 0 on the wall; epsilon: no flux
        } else if (kind == CompositeFlow::Boundary::inlet) {
          // The cell's nu_t across the half cell to the inlet (fv and
          // fv-reference take the mean of the cell's and the inlet's: both
          // first order at the face).
          for (int q = 0; q < 2; ++q) l.diffusion[q] = 2.0 * (nu_ + nut[c] * inv_sigma[q]) / (h * h);
          const auto& in = upstream_[c][s].own_inlet;
          l.boundary[0] = in[0], l.boundary[1] = in[1];
        } else {
          continue;  // outlet, symmetry: no diffusive flux, outflow at the cell's own value
        }
      }
      out[c].push_back(l);
    }
  }
  return out;
}

// Per local cell and sub-face, where the cells one further upstream are
// (the grid's value at that level: a leaf cell or the mean of finer ones;
// none where the region is coarser, or beyond a domain face but an inlet).
void CompositeTurbulence::find_upstream() {
  const auto& g = flow_.grid();
  const auto& faces = flow_.faces();
  upstream_.assign(faces.size(), {});
  auto beyond = [&](int level, const Index3& index, int axis, int side, Upstream::Kind& kind,
                    std::array<double, 2>& inlet, Stencil& out) {
    const Index3 at = shifted(index, axis, side);
    if (g.value(level, at, out)) {
      out = g.to_slots(out);
      kind = Upstream::stencil;
    } else if (g.cover(level, at) == CompositeGrid::Cover::outside &&
               flow_.boundary(2 * axis + (side > 0)) == CompositeFlow::Boundary::inlet) {
      kind = Upstream::inlet;
      inlet = inlet_(2 * axis + (side > 0), g.centre({level, index}));  // beside the cell
    }
  };
  for (std::size_t c = 0; c < faces.size(); ++c) {
    const auto cell = g.local_cell(static_cast<long>(c));
    upstream_[c].resize(faces[c].size());
    for (std::size_t s = 0; s < faces[c].size(); ++s) {
      const auto& f = faces[c][s];
      auto& u = upstream_[c][s];
      if (f.wall) {  // beyond a domain face: what enters there, if it is an inlet
        const int face = 2 * f.axis + (f.side > 0);
        if (flow_.boundary(face) == CompositeFlow::Boundary::inlet)
          u.own_inlet = inlet_(face, g.centre(cell));
        continue;
      }
      beyond(cell.level, cell.index, f.axis, -f.side, u.self_kind, u.self_inlet, u.self);
      beyond(cell.level + f.across_level, f.across_index, f.axis, f.side, u.across_kind, u.across_inlet,
             u.across);
    }
  }
}

CompositeTurbulence::CompositeTurbulence(CompositeFlow& flow, Forest& forest, const TurbulenceParams& params,
                                         double nu, int first, const std::array<double, 3>& lower,
                                         const std::array<double, 3>& upper, IjSystem::Options solve)
    : flow_(flow),
      forest_(forest),
      params_(params),
      nu_(nu),
      first_(first),
      lower_(lower),
      upper_(upper),
      solve_(solve) {
  inlet_ = [k = params.inlet_k, eps = params.inlet_epsilon](int, const std::array<double, 3>&) {
    return std::array<double, 2>{k, eps};
  };
  if (forest.spec().components < first + 3)
    throw std::invalid_argument("refinement: k-epsilon needs three components on the forest");
  find_upstream();
  update_distance();
}

double& CompositeTurbulence::at(std::size_t cell, int q) const {
  const auto per = static_cast<std::size_t>(flow_.grid().cells_per_patch());
  const auto nc = static_cast<std::size_t>(forest_.spec().components);
  return forest_.data(cell / per)[(cell % per) * nc + static_cast<std::size_t>(first_ + q)];
}

// The distance from each cell centre to the nearest wall of the box (a
// no-slip face, moving or not) and to the bodies. A centre on a body's
// surface would be at y = 0 (epsilon = 2 nu k / y^2 infinite there, and in
// its neighbours' rows): no closer to a body than a quarter of the finest
// spacing, inside the forcing's diffuse surface, as fv does.
void CompositeTurbulence::update_distance() {
  const auto& g = flow_.grid();
  const double floor = 0.25 * g.spacing(forest_.spec().max_level);
  y_.assign(static_cast<std::size_t>(g.local_cells()), std::numeric_limits<double>::infinity());
  for (long c = 0; c < g.local_cells(); ++c) {
    const auto x = g.centre(g.local_cell(c));
    double& y = y_[static_cast<std::size_t>(c)];
    for (int f = 0; f < 2 * g.dims(); ++f) {
      const auto a = static_cast<std::size_t>(f / 2);
      if (forest_.spec().periodic[a] || flow_.boundary(f) != CompositeFlow::Boundary::wall) continue;
      y = std::min(y, f % 2 == 0 ? x[a] - lower_[a] : upper_[a] - x[a]);
    }
    if (body_) y = std::min(y, std::max(body_(x), floor));
  }
}

void CompositeTurbulence::update_eddy_viscosity() {
  const Closure cl{params_.constants, nu_, params_.wall == "two-layer"};
  for (std::size_t c = 0; c < y_.size(); ++c) at(c, 2) = cl.nu_t(y_[c], at(c, 0), at(c, 1));
}

void CompositeTurbulence::set_initial() {
  const Closure cl{params_.constants, nu_, params_.wall == "two-layer"};
  for (std::size_t c = 0; c < y_.size(); ++c) {
    at(c, 0) = params_.initial_k;
    at(c, 1) =
        cl.one_equation(y_[c], at(c, 0)) ? cl.epsilon_near_wall(y_[c], at(c, 0)) : params_.initial_epsilon;
  }
  update_eddy_viscosity();
}

void CompositeTurbulence::after_regrid() {
  find_upstream();
  update_distance();
  update_eddy_viscosity();
}

void CompositeTurbulence::set_body_distance(std::function<double(const std::array<double, 3>&)> distance) {
  body_ = std::move(distance);
  update_distance();
  update_eddy_viscosity();
}

// A value that is not finite first (std::min passes over a NaN, and inf > 0):
// a flow blowing up, as fv says it; then positivity, which the scheme keeps.
void CompositeTurbulence::check_positive() const {
  double low[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(), 0.0};
  for (std::size_t c = 0; c < y_.size(); ++c) {
    low[0] = std::min(low[0], at(c, 0));
    low[1] = std::min(low[1], at(c, 1));
    if (!(std::isfinite(at(c, 0)) && std::isfinite(at(c, 1)) && std::isfinite(at(c, 2)))) low[2] = -1.0;
  }
  MPI_Allreduce(MPI_IN_PLACE, low, 3, MPI_DOUBLE, MPI_MIN, forest_.comm());
  if (low[2] < 0)
    throw std::runtime_error(
        "fv (refinement): k, epsilon or nu_t is not finite; lower fluid.fv.cfl or fluid.fv.max_step");
  if (!(low[0] > 0 && low[1] > 0))
    throw std::runtime_error(
        fmt::format("fv (refinement): k-epsilon lost positivity (min k {:.3g}, min epsilon "
                    "{:.3g}); this is a bug: please report it with the configuration",
                    low[0], low[1]));
}

void CompositeTurbulence::check_loaded(const std::string& file) const {
  double low[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(), 0.0};
  for (std::size_t c = 0; c < y_.size(); ++c) {
    const double k = at(c, 0), eps = at(c, 1);
    low[0] = std::min(low[0], k);
    low[1] = std::min(low[1], eps);
    if (!std::isfinite(params_.constants.C_mu * k * k / eps)) low[2] = -1.0;
    if (!(at(c, 2) >= 0.0 && std::isfinite(at(c, 2)))) low[2] = -1.0;  // the stored nu_t, used as it is
  }
  MPI_Allreduce(MPI_IN_PLACE, low, 3, MPI_DOUBLE, MPI_MIN, forest_.comm());
  if (!(low[0] > 0 && low[1] > 0 && low[2] == 0.0))
    throw std::runtime_error(fmt::format(
        "fv (refinement): k and epsilon must be positive, C_mu k^2 / epsilon finite and nu_t finite and not "
        "negative in {} (min k {:.3g}, min epsilon {:.3g}): the checkpoint is damaged; restart from another "
        "one",
        file, low[0], low[1]));
}

// Advection alone, in explicit sub-steps of sum |flux| dt <= 1, the face
// values limited upwind (fv::face_value, van Leer) from the four values
// along the face's axis, the same bits from either side. Each sub-step's
// new value is then at least (1 - dt sum |flux|) times the old one: the face
// values lie between 0 and twice their upwind cell's (top of the header).
void CompositeTurbulence::advect(const std::vector<std::vector<Link>>& all, double dt) {
  const auto& g = flow_.grid();
  double rate = 0.0;
  for (const auto& cell : all) {
    double sum = 0.0;
    for (const auto& l : cell) sum += std::abs(l.flux);
    rate = std::max(rate, sum);
  }
  MPI_Allreduce(MPI_IN_PLACE, &rate, 1, MPI_DOUBLE, MPI_MAX, forest_.comm());
  substeps_ = std::max(1, static_cast<int>(std::ceil(dt * rate)));
  const double h = dt / substeps_;
  std::vector<double> value[2], next[2];
  for (int step = 0; step < substeps_; ++step) {
    if (step > 0) forest_.exchange_ghosts();
    for (int q = 0; q < 2; ++q) {
      g.gather(first_ + q, value[q]);
      next[q].assign(all.size(), 0.0);
      for (std::size_t c = 0; c < all.size(); ++c) {
        const double here = value[q][c];
        double change = 0.0;
        for (const auto& l : all[c]) {
          double face = here;  // outflow through a domain face: the cell's own value
          if (l.slot >= 0)
            face = face_value(value[q], q, c, l);
          else if (l.flux < 0)
            face = l.boundary[q];
          change -= l.flux * (face - here);
        }
        next[q][c] = here + h * change;
      }
    }
    for (std::size_t c = 0; c < all.size(); ++c) {
      at(c, 0) = next[0][c];
      at(c, 1) = next[1][c];
    }
  }
}

// The limited upwind value on link l of cell c (q: one quantity, per slot).
double CompositeTurbulence::face_value(const std::vector<double>& q, int quantity, std::size_t c,
                                       const Link& l) const {
  const Upstream& u = upstream_[c][l.face];
  const double self = q[c], across = q[static_cast<std::size_t>(l.slot)];
  const auto k = static_cast<std::size_t>(quantity);
  auto far = [&](Upstream::Kind kind, const std::array<double, 2>& inlet, const Stencil& s, double near) {
    if (kind == Upstream::stencil) return evaluate(s, q);
    if (kind == Upstream::inlet) return std::max(0.0, 2.0 * inlet[k] - near);
    return near;  // first order
  };
  const double far_self = far(u.self_kind, u.self_inlet, u.self, self),
               far_across = far(u.across_kind, u.across_inlet, u.across, across);
  // Along +axis: a b | c d.
  return l.side > 0 ? fv::face_value(true, far_self, self, across, far_across, l.velocity)
                    : fv::face_value(true, far_across, across, self, far_self, l.velocity);
}

// (1/dt + sink) q' - div((nu + nu_t / sigma) grad q') = q / dt + source by
// the links' two-point fluxes, an M-matrix (positive diagonal above the sum
// of its non-positive couplings), so q' > 0 for q > 0 and source >= 0. Cells
// where `fixed` is set keep the value they hold (identity rows).
void CompositeTurbulence::diffuse(const std::vector<std::vector<Link>>& all, int q, double dt,
                                  const std::vector<double>& sink, const std::vector<double>& source,
                                  const std::vector<char>* fixed) {
  const long first = flow_.grid().first_cell();
  std::vector<Stencil> rows(all.size());
  std::vector<double> b(all.size()), x(all.size());
  for (std::size_t c = 0; c < all.size(); ++c) {
    const long self = first + static_cast<long>(c);
    x[c] = at(c, q);
    if (fixed && (*fixed)[c]) {
      rows[c] = {{self, 1.0}};
      b[c] = x[c];
      continue;
    }
    double diag = 1.0 / dt + (sink.empty() ? 0.0 : sink[c]);
    b[c] = x[c] / dt + (source.empty() ? 0.0 : source[c]);
    for (const auto& l : all[c]) {
      diag += l.diffusion[q];
      if (l.slot >= 0)
        rows[c].emplace_back(l.id, -l.diffusion[q]);
      else
        b[c] += l.diffusion[q] * l.boundary[q];
    }
    rows[c].emplace_back(self, diag);
  }
  // A hundredth of the flow's tolerance (as its viscous solves): the M-matrix
  // keeps the exact solution positive, the iterate's error must stay below
  // the smallest values.
  IjSystem::Options tight = solve_;
  tight.tolerance = std::max(1e-13, 0.01 * solve_.tolerance);
  tight.name = "k-epsilon diffusion solve (a hundredth of fluid.fv.tolerance)";
  IjSystem system(forest_.comm(), first, rows, tight);
  system.solve(b, x);
  iterations_ = std::max(iterations_, system.last_iterations());
  for (std::size_t c = 0; c < all.size(); ++c) at(c, q) = x[c];
}

void CompositeTurbulence::transport(double dt) {
  forest_.exchange_ghosts();
  const auto all = current_links();
  advect(all, dt);
  for (int q = 0; q < 2; ++q) diffuse(all, q, dt, {}, {}, nullptr);
}

std::vector<std::vector<CompositeTurbulence::Link>> CompositeTurbulence::current_links() const {
  std::vector<double> nut;
  flow_.grid().gather(first_ + 2, nut);
  return links(nut);
}

// S^2 = 2 S_ij S_ij (eqs. 3.15-3.16) from the new velocity's gradients; the
// sources from the old nu_t, k and epsilon; then transport, the sources'
// implicit step, the one-equation layer's epsilon and the new nu_t.
void CompositeTurbulence::step(double dt) {
  const auto grad = flow_.velocity_gradients();
  const Closure cl{params_.constants, nu_, params_.wall == "two-layer"};
  const int dims = flow_.grid().dims();
  std::vector<double> production(y_.size()), sink_k(y_.size()), sink_e(y_.size()), source_e(y_.size());
  for (std::size_t c = 0; c < y_.size(); ++c) {
    const auto& d = grad[c];
    double s2 = 0.0;
    for (int i = 0; i < dims; ++i) {
      s2 += 2.0 * d[i][i] * d[i][i];
      for (int j = i + 1; j < dims; ++j) s2 += (d[i][j] + d[j][i]) * (d[i][j] + d[j][i]);
    }
    const Sources q = sources(params_.constants, at(c, 2), s2, at(c, 0), at(c, 1));
    production[c] = q.production, sink_k[c] = q.sink_k, sink_e[c] = q.sink_epsilon,
    source_e[c] = q.source_epsilon;
  }
  const auto all = current_links();  // velocity_gradients() exchanged every component's ghosts
  iterations_ = 0;
  advect(all, dt);
  diffuse(all, 0, dt, sink_k, production, nullptr);
  std::vector<char> fixed(y_.size(), 0);  // the one-equation layer: epsilon of eq. 3.18 from the new k
  for (std::size_t c = 0; c < y_.size(); ++c)
    if (cl.one_equation(y_[c], at(c, 0))) {
      fixed[c] = 1;
      at(c, 1) = cl.epsilon_near_wall(y_[c], at(c, 0));
    }
  diffuse(all, 1, dt, sink_e, source_e, cl.two_layer ? &fixed : nullptr);
  check_positive();
  update_eddy_viscosity();
}

std::vector<double> CompositeTurbulence::largest_eddy_viscosity() const {
  const auto& g = flow_.grid();
  std::vector<double> most(static_cast<std::size_t>(forest_.spec().max_level + 1), 0.0);
  for (std::size_t c = 0; c < y_.size(); ++c) {
    auto& m = most[static_cast<std::size_t>(g.local_cell(static_cast<long>(c)).level)];
    m = std::max(m, at(c, 2));
  }
  MPI_Allreduce(MPI_IN_PLACE, most.data(), static_cast<int>(most.size()), MPI_DOUBLE, MPI_MAX,
                forest_.comm());
  return most;
}

double CompositeTurbulence::smallest_eddy_viscosity() const {
  double least = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < y_.size(); ++c) least = std::min(least, at(c, 2));
  MPI_Allreduce(MPI_IN_PLACE, &least, 1, MPI_DOUBLE, MPI_MIN, forest_.comm());
  return std::isfinite(least) ? least : 0.0;
}

// u_tau^2 = nu |d u_t / d n| from the cell's velocity gradient by Gauss's
// theorem (the wall's velocity on its face, the interpolated one on the
// opposite face: (u_face - U_wall) / h, below the wall's own shear, which fv
// on its uniform grid takes from a parabola through the wall and two cells),
// over the tangential components; y+ at the centre, h / 2 from the wall (a
// cell on two walls shows the larger).
std::vector<double> CompositeTurbulence::y_plus() {
  const auto grad = flow_.velocity_gradients();
  const auto& faces = flow_.faces();
  std::vector<double> out(y_.size(), 0.0);
  for (std::size_t c = 0; c < faces.size(); ++c)
    for (const auto& f : faces[c]) {
      if (!f.wall || flow_.boundary(2 * f.axis + (f.side > 0)) != CompositeFlow::Boundary::wall) continue;
      double shear2 = 0.0;
      for (int q = 0; q < flow_.grid().dims(); ++q)
        if (q != f.axis) shear2 += grad[c][q][f.axis] * grad[c][q][f.axis];
      keep_largest(out[c], 0.5 * flow_.spacing(c) * std::sqrt(nu_ * std::sqrt(shear2)) / nu_);
    }
  return out;
}

std::array<double, 3> CompositeTurbulence::totals() const {
  std::array<double, 3> sum{0.0, 0.0, 0.0};
  const int dims = flow_.grid().dims();
  for (std::size_t c = 0; c < y_.size(); ++c) {
    const double v = std::pow(flow_.spacing(c), dims);
    sum[0] += v * at(c, 0);
    sum[1] += v * at(c, 1);
    sum[2] += v;
  }
  MPI_Allreduce(MPI_IN_PLACE, sum.data(), 3, MPI_DOUBLE, MPI_SUM, forest_.comm());
  return sum;
}

}  // namespace coflow::fluid::fv::amr
