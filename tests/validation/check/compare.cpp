// coflow-check: two runs compared snapshot against snapshot.
#include "check.hpp"

namespace coflow::check {

// The largest |a_i - b_i| and the largest |a_i| of two arrays; a NaN or an
// infinity in either fails the comparison (std::max would drop a NaN).
std::pair<double, double> largest_difference(const std::vector<double>& a, const std::vector<double>& b,
                                             const char* what) {
  double diff = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!std::isfinite(a[i]) || !std::isfinite(b[i]))
      throw std::runtime_error(fmt::format("{}: value {} is not finite ({} against {})", what, i, a[i], b[i]));
    diff = nan_max(diff, std::abs(a[i] - b[i]));
    scale = nan_max(scale, std::abs(a[i]));
  }
  return {diff, scale};
}

// Particle snapshots of two runs: largest position difference over the diameter.
int compare_particles(const std::string& a, const std::string& b) {
  const auto sa = snapshots(a, "particles"), sb = snapshots(b, "particles");
  for (const auto& [dir, list] : {std::pair{&a, &sa}, std::pair{&b, &sb}})
    if (list->empty())
      throw std::runtime_error(
          fmt::format("{}: no fluid or particle snapshots to compare (run.output.every "
                      "writes them)",
                      *dir));
  const std::string fa = a + "/particles/" + output::snapshot_name(sa.back().first);
  const std::string fb = b + "/particles/" + output::snapshot_name(sb.back().first);
  // Snapshots of different rank counts hold the particles in different orders:
  // compare by id.
  auto by_id = [](const std::string& f, const std::string& name, int nc) {
    const auto id = output::read_dataset(f, "id");
    const auto v = output::read_dataset(f, name);
    std::vector<std::size_t> order(id.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](std::size_t p, std::size_t q) { return id[p] < id[q]; });
    std::vector<double> out;
    for (std::size_t i : order)
      for (int c = 0; c < nc; ++c) out.push_back(v[nc * i + c]);
    return out;
  };
  const auto xa = by_id(fa, "position", 3), xb = by_id(fb, "position", 3);
  const auto va = by_id(fa, "velocity", 3), vb = by_id(fb, "velocity", 3);
  const auto ra = by_id(fa, "radius", 1);
  if (xa.size() != xb.size()) throw std::runtime_error("particle counts differ");
  const auto [dx, xmax] = largest_difference(xa, xb, "particle positions");
  const auto [dv, vmax] = largest_difference(va, vb, "particle velocities");
  double dmin = 1e300;
  for (double r : ra) dmin = std::min(dmin, 2 * r);
  std::printf("particles=%zu\nposition_difference=%.6e\nvelocity_difference=%.6e\n", ra.size(), dx / dmin,
              vmax > 0 ? dv / vmax : dv);
  return 0;
}

int compare(const std::string& a, const std::string& b) {
  if (!std::ifstream(a + "/fluid/index.csv")) return compare_particles(a, b);
  const auto ua = output::read_dataset(last_snapshot(a), "velocity");
  const auto ub = output::read_dataset(last_snapshot(b), "velocity");
  if (ua.size() != ub.size()) throw std::runtime_error("snapshots differ in size");
  const auto [diff, scale] = largest_difference(ua, ub, "fluid velocity");
  const auto pa = output::read_dataset(last_snapshot(a), "pressure");
  const auto pb = output::read_dataset(last_snapshot(b), "pressure");
  if (pa.size() != pb.size()) throw std::runtime_error("pressure snapshots differ in size");
  const auto [pdiff, pscale] = largest_difference(pa, pb, "fluid pressure");
  // The pressure's difference relative to its largest value; where that is
  // below 1e-6 of the dynamic pressure rho U^2, relative to rho U^2: a flow
  // whose exact pressure is uniform (a Stokes layer) holds only round-off.
  const double q = fluid_params(load(a)).density * scale * scale;
  const double pref = pscale < 1e-6 * q ? q : pscale;
  std::printf("max_velocity=%.6e\nmax_difference=%.6e\npressure_difference=%.6e\n", scale,
              scale > 0 ? diff / scale : diff, pref > 0 ? pdiff / pref : pdiff);
  // Two fluids: the colour field (between -1 and 1) where the snapshots hold it.
  const auto& fields = load(a).run.output.fields;
  if (std::find(fields.begin(), fields.end(), "phase") != fields.end()) {
    const auto [phdiff, phscale] = largest_difference(output::read_dataset(last_snapshot(a), "phase"),
                                                      output::read_dataset(last_snapshot(b), "phase"), "phase");
    std::printf("phase_difference=%.6e\n", phdiff);
  }
  // Turbulence: k, epsilon and the wall cells' y+ relative to their largest values.
  for (const char* name : {"k", "epsilon", "y_plus"})
    if (std::find(fields.begin(), fields.end(), name) != fields.end()) {
      const auto [d, m] = largest_difference(output::read_dataset(last_snapshot(a), name),
                                             output::read_dataset(last_snapshot(b), name), name);
      std::printf("%s_difference=%.6e\n", name, m > 0 ? d / m : d);
    }
  // Coupled runs: the particles too.
  if (std::ifstream(a + "/particles/index.csv")) return compare_particles(a, b);
  return 0;
}

}  // namespace coflow::check
