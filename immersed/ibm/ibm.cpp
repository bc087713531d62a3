#include "immersed/ibm/ibm.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>
#include <charconv>
#include <fstream>
#include <numbers>
#include <stdexcept>

#include "coflow/log.hpp"
#include "coflow/output.hpp"
#include "coflow/session.hpp"
#include "coflow/trace.hpp"
#include "coflow/window_loop.hpp"
#include "immersed/ibm/link.hpp"
#include "immersed/ibm/markers.hpp"
#include "immersed/point/point.hpp"

namespace coflow::immersed {

namespace {

using V3 = Eigen::Vector3d;

V3 vec(const Vec3& v) { return {v[0], v[1], v[2]}; }

// A body: its surface points relative to its reference point at t = 0, and
// its motion (params.hpp): a translation plus an oscillation of its
// reference point, a rotation about it (a constant rate plus a rotary
// oscillation about the same axis: the angle phi(t) = omega t + Theta sin(w t)).
struct Body {
  std::string name;
  std::vector<ibm::SurfacePoint> points;  // x relative to the centre at t = 0
  V3 centre0 = V3::Zero();
  BodyMotion motion;
  double volume = 0.0;      // m^3 (in 2D: of the slab)
  V3 offset0 = V3::Zero();  // centroid - reference point at t = 0
  Eigen::Matrix3d inertia0 =
      Eigen::Matrix3d::Zero();  // m^5: about the reference point at t = 0, per unit density

  double w() const { return 2 * std::numbers::pi * motion.frequency; }
  V3 centre(double t) const {
    return centre0 + vec(motion.velocity) * t + vec(motion.amplitude) * std::sin(w() * t);
  }
  V3 centre_velocity(double t) const {
    return vec(motion.velocity) + vec(motion.amplitude) * w() * std::cos(w() * t);
  }
  V3 centre_acceleration(double t) const { return -vec(motion.amplitude) * w() * w() * std::sin(w() * t); }
  V3 angular_velocity(double t) const {
    return vec(motion.angular_velocity) + vec(motion.angular_amplitude) * w() * std::cos(w() * t);
  }
  V3 angular_acceleration(double t) const {
    return -vec(motion.angular_amplitude) * w() * w() * std::sin(w() * t);
  }
  Eigen::Matrix3d rotation(double t) const {
    const V3 phi = vec(motion.angular_velocity) * t + vec(motion.angular_amplitude) * std::sin(w() * t);
    const double angle = phi.norm();
    if (angle == 0.0) return Eigen::Matrix3d::Identity();
    return Eigen::AngleAxisd(angle, phi / angle).toRotationMatrix();
  }
  // The momentum and the angular momentum about the reference point of the
  // fluid the body holds (moving with it rigidly), per unit density.
  V3 held_momentum(double t) const {
    return volume * (centre_velocity(t) + angular_velocity(t).cross(rotation(t) * offset0));
  }
  V3 held_angular_momentum(double t) const {
    const Eigen::Matrix3d R = rotation(t);
    return volume * (R * offset0).cross(centre_velocity(t)) +
           R * inertia0 * R.transpose() * angular_velocity(t);
  }
};

// ibm::inertia_about as a matrix.
Eigen::Matrix3d inertia_about(const ibm::MeshVolume& mv, const V3& p) {
  const std::array<double, 9> I = ibm::inertia_about(mv, {p[0], p[1], p[2]});
  return Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(I.data());
}

Body make_body(const BodyParams& p, const ibm::GridGeometry& g, double spacing, double retraction) {
  const stl::TriangleMesh mesh = load_body_mesh(p);
  Body b;
  b.name = p.name;
  b.motion = p.motion;
  const ibm::MeshVolume mv = ibm::mesh_volume(mesh);
  const auto& cv = p.motion.centre.values;
  b.centre0 = cv.size() == 3 ? V3(cv[0], cv[1], cv[2]) : V3(mv.centroid[0], mv.centroid[1], mv.centroid[2]);
  b.volume = std::abs(mv.volume);  // validate refuses meshes that face inward (a negative volume)
  b.offset0 = V3(mv.centroid[0], mv.centroid[1], mv.centroid[2]) - b.centre0;
  if (g.dims == 2) {  // the slab of the prism: moments about z scale with its length
    const stl::MeshSummary m = stl::summarize(mesh);
    const double slab = g.h[2] / (m.upper[2] - m.lower[2]);
    // About the point in the prism's middle plane: a centre given off it in z
    // would bring the products x z and y z, which the slab does not have.
    b.inertia0 = slab * inertia_about(mv, V3(b.centre0[0], b.centre0[1], 0.5 * (m.lower[2] + m.upper[2])));
    b.volume *= slab;
    b.centre0[2] = g.lower[2] + 0.5 * g.h[2];
    b.offset0[2] = 0.0;
  } else {
    b.inertia0 = inertia_about(mv, b.centre0);
  }
  b.points = ibm::sample_surface(mesh, g, spacing);
  const double inward = retraction * g.shell();
  for (auto& pt : b.points) {
    for (int d = 0; d < 3; ++d) pt.x[d] -= b.centre0[d] + inward * pt.normal[d];
    if (g.dims == 2) pt.x[2] = 0.0;  // in the slab's middle, with the reference point: no arm along z
  }
  return b;
}

class IbmWindows final : public coupler::WindowParts {
 public:
  IbmWindows(coupler::Session& s, const IbmParams& p);
  void before_step(long w) override;
  void step(long) override {}
  void after_step(long w) override;
  void output(long w) override;
  void save(const std::string& dir) override;  // the series row being summed

 private:
  ibm::MarkerSet markers(double t) const;
  void load_row(const std::string& path);
  static constexpr const char* kRowFile = "ibm_series.csv";

  coupler::Session& s_;
  ibm::GridGeometry grid_;
  double rho_ = 1.0;
  std::vector<Body> bodies_;
  bool moving_ = false, sent_ = false;
  std::vector<double> loads_;  // per body 6, then iterations and slip: the last window's
  std::vector<double> row_;    // the same since the last row: time-weighted mean loads, most iterations, slip
  double row_time_ = 0.0;      // s the row has summed
  output::Series series_;
};

IbmWindows::IbmWindows(coupler::Session& s, const IbmParams& p)
    : s_(s), grid_(grid_geometry(s.config().domain)), rho_(s.config().resolved["fluid"]["density"].as<double>()) {
  std::vector<output::Series::Column> columns{{"time", "s"}};
  std::size_t markers = 0;
  for (const auto& bp : p.bodies) {
    bodies_.push_back(make_body(bp, grid_, p.spacing, p.retraction));
    moving_ = moving_ || bp.motion.moves();
    markers += bodies_.back().points.size();
    for (const char* c : {"_fx", "_fy", "_fz"}) columns.push_back({bp.name + c, "N"});
    for (const char* c : {"_tx", "_ty", "_tz"}) columns.push_back({bp.name + c, "N m"});
    log::info("ibm: body {}: {} markers, volume {:.6g} m^3, reference point ({:.6g}, {:.6g}, {:.6g}) m{}", bp.name,
              bodies_.back().points.size(), bodies_.back().volume, bodies_.back().centre0[0],
              bodies_.back().centre0[1], bodies_.back().centre0[2], bp.motion.moves() ? ", moving" : ", fixed");
  }
  log::info("ibm: {} markers, kernel {}, at most {} forcing iterations to a slip of {:.3g} of the flow's speed",
            markers, p.kernel, p.max_iterations, p.tolerance);
  columns.push_back({"mdf_iterations", "1"});
  columns.push_back({"slip", "m/s"});
  loads_.assign(6 * bodies_.size() + 2, 0.0);
  row_.assign(loads_.size(), 0.0);
  if (s.rank() == 0 && s.restart_window() > 0) load_row(s.restart_dir() + "/" + kRowFile);
  if (s.rank() == 0)
    series_ = output::Series(s.output_dir() + "/series/immersed.csv", columns, s.restart_window() > 0);
}

// The series row being summed goes into a checkpoint (rank 0 keeps it): its
// time, then its sums.
void IbmWindows::save(const std::string& dir) {
  if (s_.rank() != 0) return;
  std::string text = fmt::format("{:.17g}\n", row_time_);
  for (const double v : row_) text += fmt::format("{:.17g}\n", v);
  output::atomic_write(dir + "/" + kRowFile, text);
}

// A checkpoint from before the row was kept has no file: the row starts anew.
void IbmWindows::load_row(const std::string& path) {
  std::ifstream in(path);
  if (!in) return;
  if (!(in >> row_time_)) throw std::runtime_error(path + ": cannot read the time of the series row");
  std::vector<double> sums;
  for (std::string word; in >> word;) {
    double v = 0.0;
    const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), v);
    if (ec != std::errc() || end != word.data() + word.size() || !std::isfinite(v))
      throw std::runtime_error(path + ": the series row's sums are damaged: restart from another checkpoint");
    sums.push_back(v);
  }
  // Six sums a body and two (forcing iterations, slip): another body count
  // would shift the sums onto other bodies' columns.
  if (sums.size() != row_.size())
    throw std::runtime_error(fmt::format(
        "{}: the checkpoint's series row holds the sums of {} immersed bodies, and this run has {}: restart with "
        "the bodies (immersed.ibm.bodies) of the run that wrote it",
        path, sums.size() >= 2 && (sums.size() - 2) % 6 == 0 ? fmt::format("{}", (sums.size() - 2) / 6) : "?",
        bodies_.size()));
  row_ = sums;
}

ibm::MarkerSet IbmWindows::markers(double t) const {
  ibm::MarkerSet set;
  set.time = t;
  const double ratio = grid_.shell() / grid_.cell_volume();
  for (std::size_t n = 0; n < bodies_.size(); ++n) {
    const Body& b = bodies_[n];
    const V3 c = b.centre(t), vc = b.centre_velocity(t), ac = b.centre_acceleration(t);
    const V3 om = b.angular_velocity(t), al = b.angular_acceleration(t);
    const Eigen::Matrix3d R = b.rotation(t);
    set.bodies.push_back({{c[0], c[1], c[2]}, {vc[0], vc[1], vc[2]}, {ac[0], ac[1], ac[2]}});
    for (const auto& p : b.points) {
      // A rotation about a fixed axis: the tangential and centripetal accelerations.
      const V3 r = R * V3(p.x[0], p.x[1], p.x[2]), x = c + r, u = vc + om.cross(r),
               a = ac + al.cross(r) + om.cross(om.cross(r));
      const V3 nr = R * V3(p.normal[0], p.normal[1], p.normal[2]);
      set.markers.push_back({{x[0], x[1], x[2]},
                             {u[0], u[1], u[2]},
                             p.area * ratio,
                             static_cast<int>(n),
                             {a[0], a[1], a[2]},
                             {nr[0], nr[1], nr[2]}});
    }
  }
  return set;
}

// Fixed bodies: one broadcast, marked the last (the fluid receives no more).
void IbmWindows::before_step(long w) {
  if (sent_ && !moving_) return;
  const std::vector<double> packed =
      s_.rank() == 0 ? markers((w - 1) * s_.window()).pack() : std::vector<double>{};
  ibm::send_markers(s_.partner("fluid"), s_.rank(), !moving_, packed);
  sent_ = true;
}

// The fluid's loads (the forcing's reaction), plus the rate of change of the
// momentum and angular momentum of the fluid the body holds (it moves
// rigidly with the body; Uhlmann 2005): over the window, rho (P(t1) -
// P(t0)) / window, and about the reference point rho (L(t1) - L(t0)) /
// window + v_ref x rho P (a moving reference point; the window's mean of the
// ends).
void IbmWindows::after_step(long w) {
  if (s_.rank() != 0) return;
  ibm::receive_loads(s_.partner("fluid"), loads_);
  const double t0 = (w - 1) * s_.window(), t1 = w * s_.window();
  for (std::size_t n = 0; n < bodies_.size(); ++n) {
    const Body& b = bodies_[n];
    const V3 f = (b.held_momentum(t1) - b.held_momentum(t0)) / s_.window();
    const V3 moving = 0.5 * (b.centre_velocity(t0).cross(b.held_momentum(t0)) +
                             b.centre_velocity(t1).cross(b.held_momentum(t1)));
    const V3 tq = (b.held_angular_momentum(t1) - b.held_angular_momentum(t0)) / s_.window() + moving;
    for (int d = 0; d < 3; ++d) {
      loads_[6 * n + static_cast<std::size_t>(d)] += rho_ * f[d];
      loads_[6 * n + 3 + static_cast<std::size_t>(d)] += rho_ * tq[d];
    }
  }
  const std::size_t m = 6 * bodies_.size();
  for (std::size_t k = 0; k < m; ++k) row_[k] += loads_[k] * s_.window();
  row_[m] = std::max(row_[m], loads_[m]);
  row_[m + 1] = std::max(row_[m + 1], loads_[m + 1]);
  row_time_ += s_.window();
  coupler::trace().steps = static_cast<std::uint64_t>(w);
}

// A row: the loads' mean over the windows since the last row (the most
// iterations and the largest slip among them).
void IbmWindows::output(long w) {
  if (w == 0 || s_.rank() != 0 || !s_.series_due(w)) return;
  const std::size_t m = 6 * bodies_.size();
  std::vector<double> row{w * s_.window()};
  for (std::size_t k = 0; k < m; ++k) row.push_back(row_[k] / row_time_);
  row.push_back(row_[m]);
  row.push_back(row_[m + 1]);
  series_.row(row);
  for (std::size_t n = 0; n < bodies_.size(); ++n)
    for (int d = 0; d < 3; ++d)
      s_.set_final(fmt::format("immersed.{}_f{}", bodies_[n].name, "xyz"[d]), row[1 + 6 * n + static_cast<std::size_t>(d)]);
  std::fill(row_.begin(), row_.end(), 0.0);
  row_time_ = 0.0;
}

// Bodies and point particles in one run (immersed.ibm.particles: point):
// each window the markers go out first, then the particles get the fluid at
// them; after the particles' sub-steps their momentum source goes to the
// fluid and the bodies' loads come back. The fluid takes the markers, then
// sends its velocity and takes the source, before its step, and sends the
// loads after it (docs/protocol.md: the markers' broadcast must come first).
class IbmWithParticles final : public coupler::WindowParts {
 public:
  IbmWithParticles(coupler::Session& s, const IbmParams& p)
      : bodies_(s, p), particles_(make_point_windows(s, "immersed_particles")) {}
  void start(long w0) override { particles_->start(w0); }
  void before_step(long w) override {
    bodies_.before_step(w);
    particles_->before_step(w);
  }
  void step(long) override {}
  void after_step(long w) override {
    particles_->after_step(w);
    bodies_.after_step(w);
  }
  void output(long w) override {
    bodies_.output(w);
    particles_->output(w);
  }
  void save(
      const std::string& dir) override {  // the bodies' series row; the particles keep none but the time
    bodies_.save(dir);
    particles_->save(dir);
  }
  void finish() override { particles_->finish(); }

 private:
  IbmWindows bodies_;
  std::unique_ptr<coupler::WindowParts> particles_;
};

}  // namespace

void IbmMethod::run(coupler::Session& s) {
  if (!s.has_partner("fluid"))
    throw std::runtime_error("immersed.method ibm forces a fluid: the fluid section must be present");
  const bool particles = p_.particles == "point";
  if (particles && !s.has_partner("particles"))
    throw std::runtime_error(
        "immersed.ibm.particles point couples point particles: the particles section must be "
        "present");
  s.negotiate_window(0.0);
  if (particles) {
    IbmWithParticles windows(s, p_);
    coupler::run_windows(s, windows);
    return;
  }
  IbmWindows windows(s, p_);
  coupler::run_windows(s, windows);
}

}  // namespace coflow::immersed
