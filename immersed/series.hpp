// series/immersed.csv, written alike by every immersed method: per row, the
// force and torque on all particles and the solid volume the fluid cells hold,
// summed over the ranks (docs/output.md).
#pragma once

#include <mpi.h>

#include <string>

#include "coflow/output.hpp"
#include "coflow/session.hpp"

namespace coflow::immersed {

class ImmersedSeries {
 public:
  // `name`: the file in series/ (immersed.csv; ibm with point particles
  // writes the particles' totals to immersed_particles.csv beside the bodies').
  explicit ImmersedSeries(coupler::Session& s, const std::string& name = "immersed") : s_(s) {
    if (s.rank() == 0)
      series_ = output::Series(s.output_dir() + "/series/" + name + ".csv",
                               {{"time", "s"},
                                {"force_x", "N"},
                                {"force_y", "N"},
                                {"force_z", "N"},
                                {"torque_x", "N m"},
                                {"torque_y", "N m"},
                                {"torque_z", "N m"},
                                {"solid_volume", "m^3"}},
                               s.restart_window() > 0);
  }
  // Collective: when a row is due at window w (> 0), sum this rank's totals
  // (force[3], torque[3], solid volume) and write them at the window's end.
  void write(long w, const double total[7]) {
    if (w == 0 || !s_.series_due(w)) return;
    double sum[7];
    MPI_Reduce(total, sum, 7, MPI_DOUBLE, MPI_SUM, 0, s_.comm());
    const double row[] = {w * s_.window(), sum[0], sum[1], sum[2], sum[3], sum[4], sum[5], sum[6]};
    if (s_.rank() == 0) series_.row(row);
  }

 private:
  coupler::Session& s_;
  output::Series series_;
};

}  // namespace coflow::immersed
