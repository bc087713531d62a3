#include "coflow/impulse_series.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "coflow/log.hpp"

namespace coflow::coupler {

ImpulseSeries::ImpulseSeries(Session& s, const std::string& file, std::vector<std::string> names,
                             std::vector<std::size_t> slots, std::size_t slot_count, long w0)
    : s_(s), file_(file), names_(std::move(names)), slots_(std::move(slots)), sum_(3 * slot_count) {
  since_ = static_cast<double>(w0) * s.window();
  const std::string path = w0 > 0 ? s.restart_dir() + "/" + file_ + ".csv" : std::string();
  // A checkpoint of a variant that keeps no such series (lbm-reference has no
  // fluid_walls.csv; or a damaged one): the sums start at the checkpoint's
  // time, and the series file, where there is one, keeps its rows.
  const bool resumed = w0 > 0 && std::filesystem::exists(path);
  if (w0 > 0 && !resumed && s.rank() == 0 && !empty())
    log::warn(
        "{}: the checkpoint holds no {}.csv (its variant keeps none, or it is damaged): the next row of "
        "series/{}.csv is the mean from t = {:.6g} s",
        path, file_, file_, since_);
  if (resumed) load(path);
  if (s.rank() != 0 || empty()) return;
  std::vector<output::Series::Column> columns{{"time", "s"}};
  for (const auto& n : names_)
    for (const char* c : {"_fx", "_fy", "_fz"}) columns.push_back({n + c, "N"});
  series_ = output::Series(s.output_dir() + "/series/" + file_ + ".csv", columns, w0 > 0);
}

// The checkpoint's sums, on rank 0 (the others start from zero): a line per
// value, the plain sum of its non-finite terms and then its 68 digits; a
// checkpoint written before 2026-12-05 holds one number a line, the sums
// rounded, which are added exactly.
void ImpulseSeries::load(const std::string& path) {
  std::ifstream in(path);
  if (!(in >> since_)) throw std::runtime_error(path + ": cannot read the time of the last row");
  std::string line;
  std::getline(in, line);
  std::vector<std::string> lines;
  while (std::getline(in, line))
    if (line.find_first_not_of(" \t\r") != std::string::npos) lines.push_back(line);
  if (lines.size() > sum_.size())
    throw std::runtime_error(
        path + ": the checkpoint holds the impulses of more walls than this run has (" +
        std::to_string(sum_.size() / 3) +
        " slots): restart with the walls, meshes and fluid.solids of the run that wrote it");
  if (lines.size() < sum_.size())
    throw std::runtime_error(path + ": cannot read the wall impulses of the checkpoint");
  for (std::size_t i = 0; i < lines.size(); ++i) {
    std::istringstream is(lines[i]);
    std::string first;  // the non-finite part (nan, inf or -inf, which >> does not read) or the old sum
    std::vector<std::int64_t> digits;
    char* end = nullptr;
    const double special = (is >> first) ? std::strtod(first.c_str(), &end) : 0.0;
    if (first.empty() || end != first.c_str() + first.size())
      throw std::runtime_error(path + ": cannot read the wall impulses of the checkpoint");
    for (std::int64_t d = 0; is >> d;) digits.push_back(d);
    if (!is.eof() || (!digits.empty() && digits.size() != static_cast<std::size_t>(ExactSums::kDigits)))
      throw std::runtime_error(path + ": cannot read the wall impulses of the checkpoint");
    if (s_.rank() != 0) continue;
    if (digits.empty())
      sum_.add(i, special);  // the old format: the rounded sum
    else
      sum_.set(i, digits, special);
  }
}

void ImpulseSeries::add(ExactSums window) {
  if (window.size() != sum_.size()) throw std::logic_error("wall impulses for another number of walls");
  sum_.merge(std::move(window));
}

void ImpulseSeries::row(double t) {
  const double span = t - since_;
  const std::vector<double> all = sum_.reduce(s_.comm());  // zeroes the sums
  std::vector<double> values{t};
  for (const std::size_t slot : slots_)
    for (int q = 0; q < 3; ++q) values.push_back(span > 0.0 ? all[3 * slot + q] / span : 0.0);
  if (s_.rank() == 0 && !empty()) series_.row(values);
  since_ = t;
}

void ImpulseSeries::save(const std::string& dir) {
  sum_.to_root(s_.comm());  // rank 0 holds them all, exactly; a later row reduces the same
  if (s_.rank() != 0) return;
  std::string text = fmt::format("{:.17g}\n", since_);  // the last row's time: sums run from there
  for (std::size_t i = 0; i < sum_.size(); ++i) {
    text += fmt::format("{:.17g}", sum_.special(i));
    for (const std::int64_t d : sum_.canonical(i)) text += fmt::format(" {}", d);
    text += "\n";
  }
  output::atomic_write(dir + "/" + file_ + ".csv", text);
}

}  // namespace coflow::coupler
