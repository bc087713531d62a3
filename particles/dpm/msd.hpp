// The mean-square lateral displacement of point particles after they cross a
// plane (seed 003 eq. 5.24; Snyder & Lumley 1971 reset the displacement and
// the clock where each particle passes x/M = 68.4): per species, at t = 0,
// interval, 2 interval, ... after each particle's own crossing, the mean over
// the particles of (d_a^2 + d_b^2) / 2, d the displacement along the two axes
// across the plane (the flow across is isotropic: the mean of both halves the
// scatter of eq. 5.24's one axis). Written to series/dispersion.csv.
//
// Each particle carries a track of 5 numbers (it migrates with it): 0 before
// the plane, 1 after, 2 when its samples are done; the crossing time; its
// lateral displacement at the start of the step; the next sample.
#pragma once

#include <fmt/format.h>
#include <mpi.h>

#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "coflow/output.hpp"
#include "particles/dpm/forces.hpp"
#include "particles/particles_interface.hpp"

namespace coflow::particles::dpm {

class Msd {
 public:
  static constexpr int kTrack = 5;
  Msd() = default;
  Msd(const DispersionParams& p, int species)
      : on_(p.msd), axis_(p.msd_axis), a_((p.msd_axis + 1) % 3), b_((p.msd_axis + 2) % 3), plane_(p.msd_plane),
        interval_(p.msd_interval), samples_(p.msd_samples), species_(species),
        sum_(static_cast<std::size_t>(species * (p.msd_samples + 1)), 0.0), count_(sum_.size(), 0.0) {}
  bool on() const { return on_; }

  // A particle of species sp moves from x0 at t0 to x1 at t0 + h (x1 before
  // any periodic wrap).
  void step(double* tr, int sp, const V3& x0, const V3& x1, double t0, double h) {
    if (!on_ || tr[0] == 2) return;
    if (tr[0] == 0) {
      if (!(x0[axis_] < plane_ && x1[axis_] >= plane_)) return;
      const double s = (plane_ - x0[axis_]) / (x1[axis_] - x0[axis_]);
      tr[0] = 1;
      tr[1] = t0 + s * h;
      tr[2] = -s * (x1[a_] - x0[a_]);  // at t0, from the crossing point
      tr[3] = -s * (x1[b_] - x0[b_]);
      tr[4] = 0;
    }
    while (tr[4] <= samples_) {
      const double t = tr[1] + tr[4] * interval_;
      if (t > t0 + h * (1 + 1e-12)) break;
      const double r = (t - t0) / h;
      const double da = tr[2] + r * (x1[a_] - x0[a_]), db = tr[3] + r * (x1[b_] - x0[b_]);
      const auto k = static_cast<std::size_t>(sp * (samples_ + 1)) + static_cast<std::size_t>(tr[4]);
      sum_[k] += 0.5 * (da * da + db * db);
      count_[k] += 1;
      tr[4] += 1;
    }
    tr[2] += x1[a_] - x0[a_];
    tr[3] += x1[b_] - x0[b_];
    if (tr[4] > samples_) tr[0] = 2;
  }

  // Collective: the sums of all ranks on rank 0, which writes the file.
  void write(MPI_Comm comm, const std::string& path, const std::vector<std::string>& names) const {
    if (!on_) return;
    std::vector<double> sum(sum_.size()), count(count_.size());
    MPI_Reduce(sum_.data(), sum.data(), static_cast<int>(sum.size()), MPI_DOUBLE, MPI_SUM, 0, comm);
    MPI_Reduce(count_.data(), count.data(), static_cast<int>(count.size()), MPI_DOUBLE, MPI_SUM, 0, comm);
    int rank = 0;
    MPI_Comm_rank(comm, &rank);
    if (rank != 0) return;
    // The whole file at once, replaced atomically (a run killed while it
    // writes leaves the last one whole); the lag with 12 digits as the
    // series' time, the means with 17, the counts as integers.
    std::string out = "t", units = "# s";
    for (const auto& n : names) out += ",msd_" + n, units += ",m^2";
    for (const auto& n : names) out += ",n_" + n, units += ",1";
    out += "\n" + units + "\n";
    for (int k = 0; k <= samples_; ++k) {
      out += fmt::format("{:.12g}", k * interval_);
      for (int sp = 0; sp < species_; ++sp) {
        const auto i = static_cast<std::size_t>(sp * (samples_ + 1) + k);
        out += fmt::format(",{:.17g}", count[i] > 0 ? sum[i] / count[i] : 0.0);
      }
      for (int sp = 0; sp < species_; ++sp)
        out += fmt::format(",{:.0f}", count[static_cast<std::size_t>(sp * (samples_ + 1) + k)]);
      out += "\n";
    }
    output::atomic_write(path, out);
  }

  // Checkpoint: the sums (rank 0 keeps all ranks' after a restart).
  std::vector<double> totals(MPI_Comm comm) const {
    std::vector<double> all(2 * sum_.size());
    std::vector<double> mine(sum_);
    mine.insert(mine.end(), count_.begin(), count_.end());
    MPI_Reduce(mine.data(), all.data(), static_cast<int>(all.size()), MPI_DOUBLE, MPI_SUM, 0, comm);
    return all;
  }
  void set_totals(const std::vector<double>& all) {
    if (all.size() != 2 * sum_.size()) throw std::runtime_error("dpm_msd.csv does not match dispersion.msd");
    std::copy(all.begin(), all.begin() + static_cast<long>(sum_.size()), sum_.begin());
    std::copy(all.begin() + static_cast<long>(sum_.size()), all.end(), count_.begin());
  }

 private:
  bool on_ = false;
  int axis_ = 0, a_ = 1, b_ = 2;
  double plane_ = 0.0, interval_ = 0.0;
  int samples_ = 0, species_ = 0;
  std::vector<double> sum_, count_;
};

}  // namespace coflow::particles::dpm
