#include "coflow/clock.hpp"

#include <fmt/format.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "coflow/log.hpp"
#include "coflow/wait.hpp"

namespace coflow::coupler {

Clock::Clock(const config::Config& cfg, long restart_window, double restart_window_length, std::string restart_file)
    : cfg_(cfg),
      restart_window_(restart_window),
      restart_window_length_(restart_window_length),
      restart_file_(std::move(restart_file)) {}

double output_window(double step, const config::Config& cfg) {
  if (!cfg.coupling.window.is_auto) return cfg.coupling.window.value;
  const double every = cfg.run.output.every;
  if (every <= 0 || !(step > 0)) return step;
  // A step that makes `every` in a whole number to 1e-6 (a tau given with
  // that many digits for a round step) is kept: the snapshot times are then
  // exact to far below the 12 digits they are written with.
  const double ratio = every / step;
  if (std::abs(ratio - std::round(ratio)) <= 1e-6 * ratio) return step;
  const double n = std::ceil(ratio);
  const double w = every / n;
  return w >= 0.9 * step ? w : step;
}

double outputs_window(const config::Config& cfg) {
  // Nobody has a natural step: one window per output interval, or the
  // largest part of it (up to a thousandth) that also ends the run at
  // run.end_time: series every 4 s to an end of 6 s ran two windows of 4 s,
  // to t = 8 s, and now runs three of 2 s. Where none does, the whole
  // number of windows that ends at run.end_time (the rows then at the first
  // window end past each multiple, as with a step).
  const auto& o = cfg.run.output;
  const double series = o.series_every.is_auto ? o.every : o.series_every.value;
  const double end = cfg.run.end_time;
  double shortest = end;
  for (double e : {o.every, series})
    if (e > 0) shortest = std::min(shortest, e);
  const auto whole = [](double x) { return x >= 1.0 - kReach && std::abs(x - std::round(x)) <= kReach; };
  double w = end / std::max(1.0, std::ceil(end / shortest - kReach));
  for (int n = 1; n <= 1000; ++n) {
    const double c = shortest / n;
    bool fits = whole(end / c);
    for (double e : {o.every, series}) fits = fits && (e <= 0 || whole(e / c));
    if (fits) {
      w = c;
      break;
    }
  }
  return w;
}

double Clock::negotiate(double preferred) {
  const double offer = preferred > 0 ? preferred : std::numeric_limits<double>::infinity();
  double w = offer;
  // Through wait_all, so that a component that never comes (stuck in its
  // set-up, or an executable that skips negotiate_window) ends the run after
  // coupling.timeout; its time stays out of the trace's coupling wait, as
  // the blocking reduction's did.
  MPI_Request r;
  MPI_Iallreduce(&offer, &w, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD, &r);
  double start_wait = 0.0;
  wait_all({&r, 1},
           "every component to offer its time step (negotiate_window): one is still setting up after "
           "coupling.timeout, or never asks",
           &start_wait);
  if (!cfg_.coupling.window.is_auto)
    w = cfg_.coupling.window.value;
  else if (std::isfinite(w))
    w = output_window(w, cfg_);
  from_outputs_ = !std::isfinite(w);
  if (from_outputs_) w = outputs_window(cfg_);
  window_ = w;
  const double count = std::ceil(cfg_.run.end_time / w - kReach);
  // Every rank has the same window, so every rank throws.
  if (!(count <= kMostWindows))
    throw config::ConfigError({config::Problem{
        cfg_.file, 0, 0, "run.end_time",
        fmt::format("{:.6g} s is {:.3g} coupling windows of {:.6g} s, more than the {:.0e} a run can count: "
                    "shorten run.end_time or lengthen the window",
                    cfg_.run.end_time, count, w, kMostWindows)}});
  windows_ = std::max(1L, static_cast<long>(count));
  if (restart_window_ > 0 && std::abs(window_ - restart_window_length_) > 1e-12 * window_)
    throw config::ConfigError({config::Problem{
        restart_file_, 0, 0, "window_length",
        fmt::format("the checkpoint was written with windows of {:.17g} s but this run has {:.17g} s: restart "
                    "with the configuration of the run that wrote it",
                    restart_window_length_, window_)}});
  log::info("coupling window {:.6g} s, {} windows to t = {:.6g} s ({})", window_, windows_,
            cfg_.run.end_time, config::scheme_name(cfg_.coupling.scheme));
  // An automatic window need not divide run.end_time (a given one must): the
  // last window then ends past it (summary.json's time_reached).
  if (const double reached = static_cast<double>(windows_) * window_;
      reached - cfg_.run.end_time > 1e-6 * cfg_.run.end_time)  // validation's tolerance for a given window
    log::info("run.end_time {:.12g} s is not a whole number of windows: the run ends at t = {:.12g} s",
              cfg_.run.end_time, reached);
  return window_;
}

long Clock::substeps(double step) const {
  if (step <= 0) return 1;
  const double n = std::ceil(window_ / step - 1e-9);
  if (!(n <= kMostWindows))  // every rank of the component has the same step
    throw config::ConfigError({config::Problem{
        cfg_.file, 0, 0, "time_step",
        fmt::format(
            "a step of {:.6g} s is {:.3g} steps per coupling window of {:.6g} s, more than a run can count: "
            "lengthen the step",
            step, n, window_)}});
  return std::max(1L, static_cast<long>(n));
}

static bool crosses(long w, double window, double every) {
  if (every <= 0) return false;
  if (w == 0) return true;
  const double a = (w - 1) * window / every, b = w * window / every;
  return multiples_reached(b) > multiples_reached(a);
}

bool Clock::snapshot_due(long w) const {
  if (w == restart_window_ && w > 0) return false;  // the run being restarted wrote it
  return crosses(w, window_, cfg_.run.output.every) || (w == windows_ && cfg_.run.output.every > 0);
}

long Clock::snapshot_number(long w) const {
  const double every = cfg_.run.output.every;
  if (w <= 0 || every <= 0) return 0;
  const long k = static_cast<long>(multiples_reached(w * window_ / every));
  return crosses(w, window_, every) ? k : k + 1;
}

bool Clock::series_due(long w) const {
  if (w == restart_window_ && w > 0) return false;
  const auto& o = cfg_.run.output;
  const double every = o.series_every.is_auto ? o.every : o.series_every.value;
  if (every <= 0) return w == 0 || w == windows_;
  return crosses(w, window_, every) || w == windows_;
}

bool Clock::checkpoint_due(long w) const {
  const auto& c = cfg_.run.checkpoint;
  if (c.every <= 0 || w <= 0 || w == restart_window_) return false;
  const double a = (w - 1) * window_ / c.every, b = w * window_ / c.every;
  return multiples_reached(b) > multiples_reached(a);
}

}  // namespace coflow::coupler
