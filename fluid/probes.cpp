#include "fluid/probes.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace coflow::fluid {

Probes::Probes(const config::Config& cfg, const coupler::Decomposition& dec, int rank, MPI_Comm comm)
    : cfg_(cfg), dec_(dec), rank_(rank), comm_(comm) {
  const auto& o = cfg.run.output;
  for (const auto& p : o.probes) {
    const auto xs = p.samples();
    for (std::size_t k = 0; k < xs.size(); ++k) {
      samples_.push_back(stencil(xs[k]));
      const std::string base = p.points == 0 ? p.name : fmt::format("{}_{}", p.name, k);
      for (const char* c : {"_ux", "_uy", "_uz", "_p"}) columns_.push_back(base + c);
    }
  }
  for (const auto& p : o.pressure_drops) {
    drops_.push_back(drop(p));
    for (const char* c : {"_p_from", "_p_to", "_dp"}) columns_.push_back(p.name + c);
  }
  if (!samples_.empty()) ghosts_ = std::make_unique<grid::GhostExchange>(dec_, rank_, 1, 4, comm_);
}

// The cell-centred stencil of x: s = (x - lower) / h - 1/2 along each axis;
// lower corner floor(s), clamped next to walls so that the stencil stays in
// the domain (a point within half a cell of a wall takes the outermost
// centres' values); periodic axes wrap.
Probes::Stencil Probes::stencil(const config::Vec3& x) const {
  const auto& d = cfg_.domain;
  const auto h = d.spacing();
  Stencil st;
  coupler::Index3 c{};
  for (int a = 0; a < 3; ++a) {
    const long n = d.cells[a];
    const double s = (x[a] - d.lower[a]) / h[a] - 0.5;
    long i = static_cast<long>(std::floor(s));
    double t = s - static_cast<double>(i);
    if (n == 1) {
      i = 0;
      t = 0.0;
    } else if (!d.periodic[a]) {
      if (i < 0) i = 0, t = 0.0;
      if (i > n - 2) i = n - 2, t = 1.0;
      t = std::clamp(s - static_cast<double>(i), 0.0, 1.0);
    }
    c[a] = i;
    st.t[a] = t;
  }
  const coupler::Index3 w = dec_.wrap(c);
  st.owner = dec_.owner(w);
  for (int a = 0; a < 3; ++a) st.corner[a] = w[a] - dec_.block(st.owner).lo[a];
  return st;
}

// Each plane lies between two cell layers (clamped at walls as above).
Probes::Drop Probes::drop(const config::PressureDropParams& p) const {
  const auto& d = cfg_.domain;
  Drop dr;
  dr.axis = p.axis_index();
  const long n = d.cells[dr.axis];
  const double h = d.spacing()[dr.axis];
  for (int k = 0; k < 2; ++k) {
    const double s = ((k == 0 ? p.from : p.to) - d.lower[dr.axis]) / h - 0.5;
    long i = std::clamp(static_cast<long>(std::floor(s)), 0L, std::max(0L, n - 2));
    dr.cell[k][0] = i;
    dr.cell[k][1] = std::min(i + 1, n - 1);
    dr.t[k] = n == 1 ? 0.0 : std::clamp(s - static_cast<double>(i), 0.0, 1.0);
  }
  return dr;
}

void Probes::interpolate(const Stencil& s, double* out) const {
  const auto& b = ghosts_->block();
  for (int q = 0; q < 4; ++q) out[q] = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    double w = 1.0;
    long at[3];
    for (int a = 0; a < 3; ++a) {
      const int up = (corner >> a) & 1;
      w *= up ? s.t[a] : 1.0 - s.t[a];
      at[a] = s.corner[a] + up;
    }
    if (w == 0.0) continue;  // also keeps a one-cell axis from reading beyond it
    const long x = b.idx(at[0], at[1], at[2]);
    for (int q = 0; q < 4; ++q) out[q] += w * field_[4 * x + q];
  }
}

// This rank's share of each plane's fluid-weighted pressure sum and of its
// fluid share: a cell counts with its fluid fraction 1 - solid_fraction (p,
// solid: owned cells, x fastest; solid null where the solver has no solids),
// so a plane's mean is the fluid's (the intrinsic average), not lowered by the
// solid cells it crosses (whose pressure is no fluid's).
void Probes::plane_sums(const Drop& d, const double* p, const double* solid, double* sum,
                        double* fluid) const {
  const coupler::Box& own = dec_.block(rank_);
  const long n0 = own.extent(0), n1 = own.extent(1);
  for (long k = 0; k < own.extent(2); ++k)
    for (long j = 0; j < n1; ++j)
      for (long i = 0; i < n0; ++i) {
        const long g[3] = {own.lo[0] + i, own.lo[1] + j, own.lo[2] + k};
        const long c = (k * n1 + j) * n0 + i;
        const double phi = solid ? 1.0 - solid[c] : 1.0;
        for (int m = 0; m < 2; ++m) {
          const double w =
              (g[d.axis] == d.cell[m][0] ? 1.0 - d.t[m] : 0.0) + (g[d.axis] == d.cell[m][1] ? d.t[m] : 0.0);
          sum[m] += w * phi * p[c];
          fluid[m] += w * phi;
        }
      }
}

std::vector<double> Probes::sample(FluidSolver& solver) {
  std::vector<double> row(columns_.size(), 0.0);
  const auto fields = solver.fields({"velocity", "pressure", "solid_fraction"});
  const auto& u = fields[0].data;
  const auto& p = fields[1].data;
  const double* solid =
      fields.size() > 2 && fields[2].name == "solid_fraction" ? fields[2].data.data() : nullptr;
  std::size_t col = 0;
  if (ghosts_) {
    const auto& b = ghosts_->block();
    field_.assign(ghosts_->field_size(), 0.0);
    long c = 0;
    for (long k = 0; k < b.extent[2]; ++k)
      for (long j = 0; j < b.extent[1]; ++j)
        for (long i = 0; i < b.extent[0]; ++i, ++c) {
          const long x = b.idx(i, j, k);
          for (int q = 0; q < 3; ++q) field_[4 * x + q] = u[3 * c + q];
          field_[4 * x + 3] = p[c];
        }
    ghosts_->exchange(field_);
    for (const Stencil& s : samples_) {
      if (s.owner == rank_) interpolate(s, &row[col]);
      col += 4;
    }
  }
  // Per drop: the two planes' weighted sums, then their fluid shares.
  std::vector<double> planes(4 * drops_.size(), 0.0);
  for (std::size_t m = 0; m < drops_.size(); ++m)
    plane_sums(drops_[m], p.data(), solid, &planes[4 * m], &planes[4 * m + 2]);
  row.insert(row.end(), planes.begin(), planes.end());
  MPI_Allreduce(MPI_IN_PLACE, row.data(), static_cast<int>(row.size()), MPI_DOUBLE, MPI_SUM, comm_);
  col = 4 * samples_.size();
  for (std::size_t m = 0; m < drops_.size(); ++m, col += 3) {
    const double* s = &row[columns_.size() + 4 * m];
    // A plane without fluid (all solid) has no mean: NaN, as no number would be true.
    for (int k = 0; k < 2; ++k) row[col + k] = s[2 + k] > 0.0 ? s[k] / s[2 + k] : std::nan("");
    row[col + 2] = row[col] - row[col + 1];
  }
  row.resize(columns_.size());
  return row;
}

}  // namespace coflow::fluid
