#include "coflow/impulse_series.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "coflow/log.hpp"
#include "coflow/mpi_count.hpp"

namespace coflow::coupler {

ImpulseSeries::ImpulseSeries(Session& s, const std::string& file, std::vector<std::string> names,
                             std::vector<std::size_t> slots, std::size_t slot_count, long w0)
    : s_(s), file_(file), names_(std::move(names)), slots_(std::move(slots)) {
  sum_.assign(3 * slot_count, 0.0);
  since_ = static_cast<double>(w0) * s.window();
  const std::string path = w0 > 0 ? s.restart_dir() + "/" + file_ + ".csv" : std::string();
  // A checkpoint of a variant that keeps no such series (lbm-reference has no
  // fluid_walls.csv): the series starts at the checkpoint's time.
  const bool resumed = w0 > 0 && std::filesystem::exists(path);
  if (w0 > 0 && !resumed && s.rank() == 0 && !empty())
    log::info("{}: the checkpoint holds no {} (its variant keeps none): series/{}.csv starts at t = {:.6g} s",
              path, file_, file_, since_);
  if (resumed) {
    std::ifstream in(path);
    if (!(in >> since_)) throw std::runtime_error(path + ": cannot read the time of the last row");
    for (double& v : sum_)
      if (!(in >> v)) throw std::runtime_error(path + ": cannot read the wall impulses of the checkpoint");
    if (double more = 0.0; in >> more)
      throw std::runtime_error(
          path + ": the checkpoint holds the impulses of more walls than this run has (" +
          std::to_string(sum_.size() / 3) +
          " slots): restart with the walls, meshes and fluid.solids of the run that wrote it");
  }
  if (s.rank() != 0 || empty()) return;
  std::vector<output::Series::Column> columns{{"time", "s"}};
  for (const auto& n : names_)
    for (const char* c : {"_fx", "_fy", "_fz"}) columns.push_back({n + c, "N"});
  series_ = output::Series(s.output_dir() + "/series/" + file_ + ".csv", columns, resumed);
}

void ImpulseSeries::add(std::vector<double> window) {
  if (window.size() != sum_.size()) throw std::logic_error("wall impulses for another number of walls");
  MPI_Allreduce(MPI_IN_PLACE, window.data(), mpi_count(window.size(), "wall impulses"), MPI_DOUBLE, MPI_SUM,
                s_.comm());
  for (std::size_t k = 0; k < sum_.size(); ++k) sum_[k] += window[k];
}

void ImpulseSeries::add(ExactSums window) {
  if (window.size() != sum_.size()) throw std::logic_error("wall impulses for another number of walls");
  const std::vector<double> all = window.reduce(s_.comm());
  for (std::size_t k = 0; k < sum_.size(); ++k) sum_[k] += all[k];
}

void ImpulseSeries::row(double t) {
  const double span = t - since_;
  std::vector<double> values{t};
  for (const std::size_t slot : slots_)
    for (int q = 0; q < 3; ++q) values.push_back(span > 0.0 ? sum_[3 * slot + q] / span : 0.0);
  if (s_.rank() == 0 && !empty()) series_.row(values);
  std::fill(sum_.begin(), sum_.end(), 0.0);
  since_ = t;
}

void ImpulseSeries::save(const std::string& dir) const {
  if (s_.rank() != 0) return;
  std::string text = fmt::format("{:.17g}\n", since_);  // the last row's time: sums run from there
  for (const double v : sum_) text += fmt::format("{:.17g}\n", v);
  output::atomic_write(dir + "/" + file_ + ".csv", text);
}

}  // namespace coflow::coupler
