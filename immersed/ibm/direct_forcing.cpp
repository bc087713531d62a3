#include "immersed/ibm/direct_forcing.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "coflow/mpi_count.hpp"

namespace coflow::ibm {

DirectForcing::DirectForcing(Grid grid, ForcingParams params, MPI_Comm comm)
    : grid_(std::move(grid)), p_(params), comm_(comm), dims_(grid_.geometry.dims) {}

DirectForcing::Grid DirectForcing::staggered(const GridGeometry& g, std::array<bool, 3> periodic,
                                             std::function<long(int c, const std::array<long, 3>& global)> index) {
  Grid grid;
  grid.geometry = g;
  grid.periodic = periodic;
  for (int c = 0; c < g.dims; ++c) {
    Points pts;
    pts.offset = {0.5, 0.5, 0.5};
    pts.offset[static_cast<std::size_t>(c)] = 0.0;
    pts.index = [index, c](const std::array<long, 3>& x) { return index(c, x); };
    grid.components.push_back(std::move(pts));
  }
  return grid;
}

DirectForcing::Grid DirectForcing::collocated(const GridGeometry& g, std::array<bool, 3> periodic,
                                              std::function<long(const std::array<long, 3>& global)> index) {
  Grid grid;
  grid.geometry = g;
  grid.periodic = periodic;
  for (int c = 0; c < g.dims; ++c) grid.components.push_back({{0.5, 0.5, 0.5}, index});
  return grid;
}

void DirectForcing::set_markers(MarkerSet markers) {
  set_ = std::move(markers);
  moving_ = false;
  for (const auto& m : set_.markers)
    for (int d = 0; d < 3; ++d) moving_ = moving_ || m.u[d] != 0.0 || m.a[d] != 0.0;
  for (const auto& b : set_.bodies)
    for (int d = 0; d < 3; ++d) moving_ = moving_ || b.velocity[d] != 0.0 || b.acceleration[d] != 0.0;
  if (loads_.size() != 6 * set_.bodies.size()) loads_.assign(6 * set_.bodies.size(), 0.0);
  placed_at_ = -1.0;
}

// The markers at time t, moved on from their set's time with their velocity
// and acceleration, their velocities there, and their stencils: built again
// only when they moved.
void DirectForcing::place(double t) {
  if (placed_at_ >= 0 && (!moving_ || placed_at_ == t)) return;
  const double dt = t - set_.time;
  x_.resize(set_.markers.size());
  target_.resize(set_.markers.size());
  for (std::size_t m = 0; m < x_.size(); ++m) {
    x_[m] = set_.markers[m].x_at(dt);
    target_[m] = set_.markers[m].u_at(dt);
  }
  placed_at_ = t;
  build_stencils();
}

// Per component and marker, the points of this rank within the kernel's
// support with their weights phi(r_x) phi(r_y) phi(r_z) (periodic axes wrap).
void DirectForcing::build_stencils() {
  const auto& g = grid_.geometry;
  const double radius = kernel_radius(p_.kernel);
  const std::size_t nc = grid_.components.size(), nm = x_.size();
  start_.assign(nc, std::vector<std::size_t>(nm + 1, 0));
  entries_.assign(nc, {});
  slot_.assign(nc, {});
  slots_.assign(3 * nm, 0);
  for (std::size_t c = 0; c < nc; ++c) {
    const Points& pts = grid_.components[c];
    for (std::size_t m = 0; m < nm; ++m) {
      std::array<std::vector<std::pair<long, double>>, 3> axis;  // per axis: index, weight
      for (int d = 0; d < 3; ++d) {
        if (d >= dims_) {
          axis[static_cast<std::size_t>(d)] = {{0, 1.0}};
          continue;
        }
        const double s = (x_[m][d] - g.lower[d]) / g.h[d] - pts.offset[d];
        for (auto i = static_cast<long>(std::ceil(s - radius)); i <= static_cast<long>(std::floor(s + radius)); ++i) {
          const double w = kernel(p_.kernel, s - static_cast<double>(i));
          if (w <= 0.0) continue;
          long at = i;
          if (grid_.periodic[d]) at = ((i % g.cells[d]) + g.cells[d]) % g.cells[d];
          axis[static_cast<std::size_t>(d)].push_back({at, w});
        }
      }
      int slot = 0;
      for (const auto& [k, wz] : axis[2])
        for (const auto& [j, wy] : axis[1])
          for (const auto& [i, wx] : axis[0]) {
            const long idx = pts.index({i, j, k});
            if (idx >= 0) entries_[c].push_back({idx, wx * wy * wz}), slot_[c].push_back(slot);
            ++slot;
          }
      start_[c][m + 1] = entries_[c].size();
      slots_[3 * m + c] = slot;
    }
  }
  lay_out_split();
  touched_.clear();
  for (const auto& list : entries_)
    for (const Entry& e : list) touched_.push_back(e.index);
  std::sort(touched_.begin(), touched_.end());
  touched_.erase(std::unique(touched_.begin(), touched_.end()), touched_.end());
  // cg's zeroed copies of the grid reach the highest point touched (sized here, not per iteration).
  const std::size_t top = touched_.empty() ? 0 : static_cast<std::size_t>(touched_.back()) + 1;
  if (p_.conjugate_gradients)
    for (std::size_t c = 0; c < nc; ++c)
      if (scratch_[c].size() < top) scratch_[c].assign(top, 0.0);
}

// Which stencils lie on several ranks (the ranks holding part of each,
// summed over the ranks), and where their terms go in interpolate's reduction.
void DirectForcing::lay_out_split() {
  const std::size_t nm = x_.size();
  std::vector<int> holders(3 * nm, 0);
  for (std::size_t c = 0; c < grid_.components.size(); ++c)
    for (std::size_t m = 0; m < nm; ++m) holders[3 * m + c] = start_[c][m + 1] > start_[c][m] ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, holders.data(), static_cast<int>(holders.size()), MPI_INT, MPI_SUM, comm_);
  split_at_.assign(3 * nm, -1);
  long next = static_cast<long>(3 * nm);
  for (std::size_t k = 0; k < 3 * nm; ++k)
    if (holders[k] > 1) split_at_[k] = next, next += slots_[k];
  coupler::mpi_count(static_cast<std::size_t>(next), "the immersed boundary's forcing reduction");
  reduced_.resize(static_cast<std::size_t>(next));
}

// A stencil on one rank is summed there, in its order; one on several ranks
// goes term by term into the reduction (each term from the one rank holding
// it, zeros from the others: exact), and every rank then sums its terms in
// the stencil's order, the points that are no unknown adding 0. So a sum
// does not depend on how the blocks cut the stencil: the same bits on any
// number of ranks (the products are rounded alike on every path: this file
// is compiled without fused multiply-adds).
void DirectForcing::interpolate(const std::array<double*, 3>& u, std::vector<double>& out) const {
  const std::size_t nm = x_.size();
  std::fill(reduced_.begin(), reduced_.end(), 0.0);
  for (std::size_t c = 0; c < grid_.components.size(); ++c) {
    const double* v = u[c];
    for (std::size_t m = 0; m < nm; ++m) {
      const long at = split_at_[3 * m + c];
      if (at >= 0) {
        for (std::size_t e = start_[c][m]; e < start_[c][m + 1]; ++e)
          reduced_[static_cast<std::size_t>(at + slot_[c][e])] =
              entries_[c][e].weight * v[entries_[c][e].index];
        continue;
      }
      double sum = 0.0;
      for (std::size_t e = start_[c][m]; e < start_[c][m + 1]; ++e)
        sum += entries_[c][e].weight * v[entries_[c][e].index];
      reduced_[3 * m + c] = sum;
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, reduced_.data(), static_cast<int>(reduced_.size()), MPI_DOUBLE, MPI_SUM, comm_);
  out.assign(reduced_.begin(), reduced_.begin() + static_cast<long>(3 * nm));
  for (std::size_t k = 0; k < out.size(); ++k)
    if (const long at = split_at_[k]; at >= 0) {
      double sum = 0.0;
      for (long s = 0; s < slots_[k]; ++s) sum += reduced_[static_cast<std::size_t>(at + s)];
      out[k] = sum;
    }
}

void DirectForcing::spread(const std::array<double*, 3>& u, const std::vector<double>& du) const {
  for (std::size_t c = 0; c < grid_.components.size(); ++c) {
    double* v = u[c];
    for (std::size_t m = 0; m < x_.size(); ++m) {
      const double amount = du[3 * m + c] * set_.markers[m].volume_ratio;
      for (std::size_t e = start_[c][m]; e < start_[c][m + 1]; ++e) v[entries_[c][e].index] += entries_[c][e].weight * amount;
    }
  }
}

DirectForcing::Result DirectForcing::apply(const std::array<double*, 3>& u, double t, double scale,
                                           double factor, double dt, const double* density) {
  Result r;
  if (set_.markers.empty()) return r;
  place(t);
  // The same scale on every rank (their iterations must match): the flow's
  // and the markers' largest speed; a fluid at rest about a fixed body takes
  // the tolerance in its own units.
  for (const auto& v : target_) scale = std::max(scale, std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) / unit_);
  MPI_Allreduce(MPI_IN_PLACE, &scale, 1, MPI_DOUBLE, MPI_MAX, comm_);
  if (!(scale > 0)) scale = 1.0;
  std::vector<double> total(3 * x_.size(), 0.0);
  r = p_.conjugate_gradients ? solve_cg(u, scale, total) : iterate_mdf(u, scale, total);
  if (!std::isfinite(r.slip))  // a NaN slip read as converged, and the maxima below dropped it
    throw std::runtime_error(
        "ibm: the fluid velocity at the body markers is not finite (the flow has blown up; lower the fluid's "
        "time step)");
  add_loads(total, factor, dt, density);
  worst_.iterations = std::max(worst_.iterations, r.iterations);
  worst_.slip = std::max(worst_.slip, r.slip);
  return r;
}

// b = U_b - I u per marker and component; returns the largest |b_m|.
double DirectForcing::slip(const std::vector<double>& at, std::vector<double>& b) const {
  double worst = 0.0;
  b.assign(at.size(), 0.0);
  for (std::size_t m = 0; m < x_.size(); ++m) {
    double s2 = 0.0;
    for (std::size_t c = 0; c < grid_.components.size(); ++c) {
      b[3 * m + c] = target_[m][c] / unit_ - at[3 * m + c];
      s2 += b[3 * m + c] * b[3 * m + c];
    }
    const double s = std::sqrt(s2);
    worst = s > worst || std::isnan(s) ? s : worst;  // NaN kept: it stops the forcing (apply)
  }
  return worst;
}

// The seed's multi-direct forcing: direct forcing repeated on the forced
// velocity (a Richardson iteration on I S x = b).
DirectForcing::Result DirectForcing::iterate_mdf(const std::array<double*, 3>& u, double scale,
                                                 std::vector<double>& total) {
  Result r;
  std::vector<double> at, du;
  for (;;) {
    interpolate(u, at);
    r.slip = slip(at, du);
    if (!(r.slip > p_.tolerance * scale) || r.iterations == p_.max_iterations) return r;
    for (std::size_t k = 0; k < du.size(); ++k) total[k] += du[k];
    spread(u, du);
    ++r.iterations;
  }
}

// The same equations for all markers at once, I S x = b (S with the
// markers' volumes D: I S = K D, K = I I^T symmetric), by conjugate gradients
// on D^1/2 K D^1/2 y = D^1/2 b, x = D^-1/2 y; each product spreads onto a
// zeroed copy of the grid and interpolates back. Then x is spread once.
DirectForcing::Result DirectForcing::solve_cg(const std::array<double*, 3>& u, double scale,
                                              std::vector<double>& total) {
  Result r;
  std::vector<double> at, b;
  interpolate(u, at);
  r.slip = slip(at, b);
  const std::size_t n = b.size();
  std::vector<double> root(n), y(n, 0.0), res(n), p(n), q(n), x(n);
  for (std::size_t k = 0; k < n; ++k) {
    root[k] = std::sqrt(set_.markers[k / 3].volume_ratio);
    res[k] = p[k] = root[k] * b[k];
  }
  auto dot = [n](const std::vector<double>& a, const std::vector<double>& c) {
    double s = 0.0;
    for (std::size_t k = 0; k < n; ++k) s += a[k] * c[k];
    return s;
  };
  double rr = dot(res, res);
  double left = r.slip;
  while (left > p_.tolerance * scale && r.iterations < p_.max_iterations && rr > 0) {
    for (std::size_t k = 0; k < n; ++k) x[k] = p[k] / root[k];
    apply_operator(x, q);
    for (std::size_t k = 0; k < n; ++k) q[k] *= root[k];
    const double pq = dot(p, q);
    if (!(pq > 0)) break;  // p in K's null space (markers sharing a stencil): no further descent
    const double alpha = rr / pq;
    for (std::size_t k = 0; k < n; ++k) y[k] += alpha * p[k], res[k] -= alpha * q[k];
    const double next = dot(res, res);
    for (std::size_t k = 0; k < n; ++k) p[k] = res[k] + next / rr * p[k];
    rr = next;
    ++r.iterations;
    left = 0.0;  // the largest slip the solution so far leaves, per marker
    for (std::size_t m = 0; m < x_.size(); ++m)
      left = std::max(left, std::sqrt(res[3 * m] * res[3 * m] + res[3 * m + 1] * res[3 * m + 1] +
                                      res[3 * m + 2] * res[3 * m + 2]) / root[3 * m]);
  }
  for (std::size_t k = 0; k < n; ++k) total[k] = y[k] / root[k];
  spread(u, total);
  interpolate(u, at);
  r.slip = slip(at, b);
  return r;
}

// q = I S x on a zeroed copy of the grid's points (the touched ones zeroed again after).
void DirectForcing::apply_operator(const std::vector<double>& x, std::vector<double>& q) {
  std::array<double*, 3> s{nullptr, nullptr, nullptr};
  for (std::size_t c = 0; c < grid_.components.size(); ++c) s[c] = scratch_[c].data();
  spread(s, x);
  interpolate(s, q);
  for (std::size_t c = 0; c < grid_.components.size(); ++c)
    for (const Entry& e : entries_[c]) scratch_[c][static_cast<std::size_t>(e.index)] = 0.0;
}

// The force on the fluid is factor sum_m dU_m Delta V_m (eq. 4.10 summed over
// the grid: the kernel sums to one), or with a density rho_x at the points
// factor sum_m dU_m Delta V_m sum_x D_h(x - X_m) rho_x (the interpolated
// density); the body takes its opposite.
void DirectForcing::add_loads(const std::vector<double>& total, double factor, double dt,
                              const double* density) {
  const double dv = grid_.geometry.cell_volume();
  std::vector<double> rho(total.size(), 1.0);
  if (density) {
    auto* d = const_cast<double*>(density);  // interpolate reads it only
    interpolate({d, d, d}, rho);
  }
  const double shift = placed_at_ - set_.time;
  for (std::size_t m = 0; m < x_.size(); ++m) {
    const Marker& mk = set_.markers[m];
    const auto b = static_cast<std::size_t>(mk.body);
    const BodyFrame& f = set_.bodies[b];
    Vec force, arm;
    for (int d = 0; d < 3; ++d) {
      const std::size_t k = 3 * m + static_cast<std::size_t>(d);
      force[d] = -factor * total[k] * rho[k] * mk.volume_ratio * dv;
      arm[d] = x_[m][d] - (f.centre[d] + (f.velocity[d] + 0.5 * f.acceleration[d] * shift) * shift);
    }
    double* l = &loads_[6 * b];
    for (int d = 0; d < 3; ++d) l[d] += force[d] * dt;
    l[3] += (arm[1] * force[2] - arm[2] * force[1]) * dt;
    l[4] += (arm[2] * force[0] - arm[0] * force[2]) * dt;
    l[5] += (arm[0] * force[1] - arm[1] * force[0]) * dt;
  }
  load_time_ += dt;
}

std::vector<double> DirectForcing::take_loads() {
  std::vector<double> out(loads_.size(), 0.0);
  if (load_time_ > 0)
    for (std::size_t k = 0; k < out.size(); ++k) out[k] = loads_[k] / load_time_;
  std::fill(loads_.begin(), loads_.end(), 0.0);
  load_time_ = 0.0;
  worst_ = {};
  return out;
}

std::vector<double> DirectForcing::take_report() {
  const Result w = worst_;
  std::vector<double> out = take_loads();
  out.push_back(w.iterations);
  out.push_back(w.slip * unit_);  // the grid's units to m/s
  return out;
}

}  // namespace coflow::ibm
