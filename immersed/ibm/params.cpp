#include "immersed/ibm/params.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "immersed/ibm/markers.hpp"

namespace coflow::immersed {

bool BodyMotion::moves() const {
  for (int d = 0; d < 3; ++d)
    if (velocity[d] != 0.0 || (amplitude[d] != 0.0 && frequency != 0.0)) return true;
  return turns();
}

bool BodyMotion::turns() const {
  for (int d = 0; d < 3; ++d)
    if (angular_velocity[d] != 0.0 || (angular_amplitude[d] != 0.0 && frequency != 0.0)) return true;
  return false;
}

// The rotation keeps one axis: a constant rotation and a rotary oscillation
// about different axes would need the composition of the two, not their sum.
static void check_axes(config::Visitor& s, const BodyMotion& m) {
  const Vec3 &w = m.angular_velocity, &a = m.angular_amplitude;
  const double cross[3] = {w[1] * a[2] - w[2] * a[1], w[2] * a[0] - w[0] * a[2], w[0] * a[1] - w[1] * a[0]};
  const double wn = std::hypot(w[0], w[1], w[2]), an = std::hypot(a[0], a[1], a[2]);
  if (std::hypot(cross[0], cross[1], cross[2]) > 1e-12 * wn * an)
    s.fail("angular_amplitude",
           "not parallel to angular_velocity: a body turns about one axis; give both along it");
}

void BodyParams::visit(config::Visitor& v) {
  v.required("name", name, "the body's name: its columns in series/immersed.csv are <name>_fx ... <name>_tz");
  v.required("mesh", mesh,
             "a closed triangle mesh (STL, ASCII or binary), relative to this file; in a 2D fluid a prism along z "
             "(its length does not matter)");
  v("scale", scale, "factor applied to the file's coordinates (0.001 for a mesh drawn in millimetres)",
    config::positive());
  v("translate", translate, "shift in m applied after the scale");
  v.section("motion", "prescribed motion (none given: the body is fixed)", [&](config::Visitor& s) {
    s("centre", motion.centre,
      "[x, y, z] m: the reference point at t = 0: rotations turn about it, torques are taken about it (none "
      "given: the mesh's centroid)");
    if (s.reading() && !motion.centre.values.empty() && motion.centre.values.size() != 3)
      s.fail("centre", fmt::format("{} numbers; give three, [x, y, z] in m", motion.centre.values.size()));
    s("velocity", motion.velocity, "m/s: a constant translation of the whole body");
    s("angular_velocity", motion.angular_velocity, "rad/s: a constant rotation about the reference point");
    s("amplitude", motion.amplitude,
      "m: a periodic oscillation, displacement amplitude sin(2 pi frequency t), added to the translation");
    s("angular_amplitude", motion.angular_amplitude,
      "rad: a periodic rotation about the reference point, angle |a| sin(2 pi frequency t) about a's "
      "direction, "
      "added to the constant rotation (about the same axis)");
    s("frequency", motion.frequency, "Hz: of the oscillations", config::at_least(0.0));
    if (s.reading()) check_axes(s, motion);
  });
}

void IbmParams::visit(config::Visitor& v) {
  v("kernel", kernel,
    "interpolation and spreading kernel (seed 003 eqs. 4.9-4.10): hat (the seed's, a linear hat of 2 cells), "
    "roma3 (Roma, Peskin & Berger 1999, 3 cells) or peskin4 (Peskin 2002, 4 cells)",
    config::one_of(ibm::kernel_names()));
  v("spacing", spacing,
    "cells between markers: the surface is sampled in boxes of this many cells, one marker per box, whatever "
    "the mesh's own triangle sizes",
    config::greater(0.0));
  v("retraction", retraction,
    "cells: each marker moved this far into the body along the surface's normal, against the kernel's "
    "thickening of the surface (Breugem 2012 calibrated 0.3 for the 3-point kernel); 0: on the surface",
    config::in_range(0.0, 1.0));
  v("iteration", iteration,
    "mdf: the seed's multi-direct forcing, direct forcing repeated on the forced velocity (Wang, Fan & Luo 2008; "
    "a Richardson iteration, slow on fine marker sets); cg: the same forcing equations for all markers at once "
    "by conjugate gradients (the same work per iteration, far fewer iterations)",
    config::one_of({"mdf", "cg"}));
  v("stage", stage,
    "fv: where the forcing acts in the step. after_predictor: the seed's (seed 003 eqs. 4.7-4.11), on u* "
    "after the implicit momentum predictor; that step's implicit diffusion never sees the force, so a steady "
    "state depends on nu dt / h^2 (circular Couette at nu dt / h^2 = 7.3: torque 27 % low). in_predictor: "
    "the "
    "force found on an explicit estimate of u* (the implicit diffusion taken at the old velocity) and added "
    "to "
    "the implicit predictor's right-hand side (the force then enters the momentum balance it corrects; a "
    "steady state has no slip whatever the step). lbm: either (its collision is explicit); the adaptive "
    "grid: "
    "after_predictor only",
    config::one_of({"after_predictor", "in_predictor"}));
  v("max_iterations", max_iterations, "the most forcing iterations in a step", config::in_range(1, 1000));
  v("tolerance", tolerance,
    "multi-direct forcing: iterate until the largest slip |U_b - U| at the markers is below this fraction of "
    "the flow's largest velocity",
    config::greater(0.0));
  v("particles", particles,
    "none: the bodies alone; point: also couple point particles (particles.solver dpm) to the fluid as "
    "method "
    "point does, in the same windows (the flow around a body carrying particles, seed 003 §5.3; "
    "serial-explicit)",
    config::one_of({"none", "point"}));
  v.list("bodies",
         "the immersed bodies, each a closed triangle mesh wound counter-clockwise seen from outside (every "
         "edge shared by two triangles that run along it in opposite directions)",
         [&](config::Visitor& s) {
           bodies.emplace_back();
           bodies.back().visit(s);
         });
}

stl::TriangleMesh load_body_mesh(const BodyParams& b) {
  stl::TriangleMesh m = stl::read(b.mesh.path);
  stl::transform(m, b.scale, stl::V3(b.translate[0], b.translate[1], b.translate[2]));
  return m;
}

ibm::GridGeometry grid_geometry(const config::DomainParams& d) {
  ibm::GridGeometry g;
  const Vec3 h = d.spacing();
  for (int k = 0; k < 3; ++k) {
    g.lower[k] = d.lower[k];
    g.cells[k] = d.cells[k];
    g.h[k] = h[k];
  }
  g.dims = d.two_dimensional() ? 2 : 3;
  return g;
}

IbmParams read_ibm_params(const config::Config& cfg) {
  IbmParams p;
  config::Reader r(cfg.resolved["immersed"]["ibm"], cfg.file, "immersed.ibm");
  p.visit(r);
  r.check();
  return p;
}

std::unique_ptr<ibm::DirectForcing> staggered_forcing(const config::Config& cfg, std::array<bool, 3> periodic,
                                                      std::function<long(int, const std::array<long, 3>&)> index,
                                                      MPI_Comm comm) {
  return std::make_unique<ibm::DirectForcing>(
      ibm::DirectForcing::staggered(grid_geometry(cfg.domain), periodic, std::move(index)),
      read_ibm_params(cfg).forcing(), comm);
}

std::unique_ptr<ibm::DirectForcing> collocated_forcing(const config::Config& cfg,
                                                       std::function<long(const std::array<long, 3>&)> index,
                                                       double velocity_unit, MPI_Comm comm) {
  const config::DomainParams& d = cfg.domain;
  const std::array<bool, 3> periodic{d.periodic[0], d.periodic[1], d.periodic[2]};
  auto forcing = std::make_unique<ibm::DirectForcing>(
      ibm::DirectForcing::collocated(grid_geometry(d), periodic, std::move(index)),
      read_ibm_params(cfg).forcing(), comm);
  forcing->set_velocity_unit(velocity_unit);
  return forcing;
}

namespace {

// The box a body sweeps until end_time: its mesh's box moved by the
// translation, grown by the oscillation and, when it turns, by its reach
// from the centre.
void swept_box(const BodyParams& b, const stl::MeshSummary& m, const stl::TriangleMesh& mesh, double end_time,
               int dims, stl::V3& lo, stl::V3& hi) {
  lo = m.lower;
  hi = m.upper;
  const auto& mo = b.motion;
  const auto& cv = mo.centre.values;
  const ibm::MeshVolume mv = ibm::mesh_volume(mesh);  // the reference point by default (ibm.cpp)
  const stl::V3 c = cv.size() == 3 ? stl::V3(cv[0], cv[1], cv[2]) : stl::V3(mv.centroid[0], mv.centroid[1], mv.centroid[2]);
  const bool turns = mo.turns();
  double reach = 0.0;
  if (turns)
    for (const auto& x :
         mesh.vertices)  // in 2D in the plane: the prism's length and the centre's z do not count
      reach = std::max(reach, dims == 2 ? std::hypot(x[0] - c[0], x[1] - c[1]) : (x - c).norm());
  for (int d = 0; d < 3; ++d) {
    if (turns) lo[d] = c[d] - reach, hi[d] = c[d] + reach;
    const double shift = mo.velocity[d] * end_time;
    lo[d] += std::min(0.0, shift) - std::abs(mo.amplitude[d]);
    hi[d] += std::max(0.0, shift) + std::abs(mo.amplitude[d]);
  }
}

}  // namespace

// The bodies: unique names, closed meshes, inside the domain with the
// kernel's support off every face that is not periodic, for the whole run.
void IbmParams::check(config::Visitor& v, const config::Config& cfg) const {
  const double radius = ibm::kernel_radius(ibm::kernel_from_name(kernel));
  if (spacing > radius)
    v.fail("spacing", fmt::format("markers {} cells apart leave gaps between the supports of kernel {} (radius {} "
                                  "cells): at most {}",
                                  spacing, kernel, radius, radius));
  if (bodies.empty()) v.fail("bodies", "no bodies: give at least one {name, mesh}");
  std::set<std::string> names;
  const Vec3 h = cfg.domain.spacing();
  const int dims = cfg.domain.two_dimensional() ? 2 : 3;
  for (std::size_t n = 0; n < bodies.size(); ++n) {
    const BodyParams& b = bodies[n];
    if (!names.insert(b.name).second)
      v.fail(fmt::format("bodies[{}]", n), fmt::format("the name '{}' is taken twice", b.name));
    if (b.name.empty() || b.name.find_first_of(", \t\"\n\r") != std::string::npos)
      v.fail(fmt::format("bodies[{}]", n),
             fmt::format("the name '{}' is not a plain word (it names the columns of "
                         "series/immersed.csv, <name>_fx ...)",
                         b.name));
    try {
      const stl::TriangleMesh mesh = load_body_mesh(b);
      const stl::MeshSummary m = stl::summarize(mesh);
      if (!m.closed)
        v.fail(fmt::format("bodies[{}].mesh", n),
               fmt::format("body '{}': the mesh {} is open ({} edges of one triangle); a body needs a "
                           "closed surface (every edge shared by two triangles), whose inside is the body",
                           b.name, b.mesh.path, m.open_edges));
      if (m.closed && m.same_way_edges > 0)
        v.fail(fmt::format("bodies[{}].mesh", n),
               fmt::format("body '{}': the mesh {} has triangles wound against their neighbours ({} edges "
                           "run the same way in both of their triangles), so some of its normals point "
                           "inward and its volume and inertia are wrong: wind every triangle the same way "
                           "round (counter-clockwise seen from outside)",
                           b.name, b.mesh.path, m.same_way_edges));
      else if (m.closed && ibm::mesh_volume(mesh).volume < 0.0)
        v.fail(fmt::format("bodies[{}]", n),
               fmt::format("body '{}': the mesh's triangles face inward (their winding encloses a "
                           "negative volume), so its markers would retract into the fluid and its "
                           "inertia change sign: reverse the order of each triangle's vertices",
                           b.name));
      const auto& mo = b.motion;
      if (dims == 2 &&
          (mo.angular_velocity[0] != 0.0 || mo.angular_velocity[1] != 0.0 || mo.angular_amplitude[0] != 0.0 ||
           mo.angular_amplitude[1] != 0.0 || mo.velocity[2] != 0.0 || mo.amplitude[2] != 0.0))
        v.fail(fmt::format("bodies[{}]", n),
               fmt::format("body '{}': the fluid is 2D: a body moves in the x-y plane and turns "
                           "about z; give its velocity and amplitude no z component and its "
                           "angular_velocity and angular_amplitude only a z component",
                           b.name));
      if (dims == 2 && !(m.upper[2] > m.lower[2]))
        v.fail(fmt::format("bodies[{}]", n),
               fmt::format("body '{}': the fluid is 2D and this mesh is flat in z; give a prism "
                           "along z (any length)",
                           b.name));
      stl::V3 lo, hi;
      swept_box(b, m, mesh, cfg.run.end_time, dims, lo, hi);
      for (int d = 0; d < dims; ++d) {
        if (cfg.domain.periodic[d]) continue;
        const double margin = (radius + 1.0) * h[d];
        if (lo[d] < cfg.domain.lower[d] + margin || hi[d] > cfg.domain.upper[d] - margin)
          v.fail(fmt::format("bodies[{}]", n),
                 fmt::format("body '{}' spans {:.6g} to {:.6g} m along {} until end_time; it must "
                             "stay {:.3g} m ({} cells: the kernel's support and one) inside the domain "
                             "[{:.6g}, {:.6g}] m: move it (translate, motion) or widen the domain",
                             b.name, lo[d], hi[d], "xyz"[d], margin, radius + 1.0, cfg.domain.lower[d],
                             cfg.domain.upper[d]));
      }
    } catch (const std::runtime_error& e) {
      v.fail(fmt::format("bodies[{}].mesh", n), fmt::format("body '{}': {}", b.name, e.what()));
    }
  }
}

}  // namespace coflow::immersed
