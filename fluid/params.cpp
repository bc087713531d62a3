#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "fluid/params.hpp"

namespace coflow::fluid {

void BoundaryParams::visit(config::Visitor& v) {
  v.required(
      "type", type,
      "wall (lbm: half-way bounce-back, the wall half a cell beyond the centres of the face's cells; fv: on "
      "the face), pressure or velocity (lbm: imposed at the centres of the face's cells; fv: on the face), "
      "outflow (zero gradient; lbm: the populations entering copied from the next cell in, post-collision, "
      "which holds no pressure level: behind a velocity inlet the fluid's mass and pressure level drift as "
      "the "
      "run goes, where a pressure face would hold them; fv: the normal velocity convective, du/dt + U du/dn "
      "= 0 with U "
      "the face's mean outward velocity, the tangential ones of zero gradient, at the reference pressure), "
      "or "
      "symmetry "
      "(fv: no flow through the face, no shear on it)",
      config::one_of({"wall", "pressure", "velocity", "outflow", "symmetry"}));
  v("value", value,
    "pressure in Pa, relative to the reference pressure (type pressure; with fluid.turbulence the modified "
    "pressure p + 2/3 rho k of seed 003 eq. 3.11, as OpenFOAM's), or velocity [u, v, w] in m/s (type "
    "velocity)");
  v("ramp", ramp,
    "s: the value rises linearly from zero (gauge pressure 0, fluid at rest) to `value` over this time, instead of "
    "starting at once",
    config::at_least(0.0));
  v("closure", closure,
    "lbm: how a pressure or velocity face sets its populations: regularized (Latt et al. 2008; auto for pressure "
    "faces: no odd-even oscillation) or zou-he (Zou & He 1997; auto for velocity faces)",
    config::one_of({"auto", "regularized", "zou-he"}));
  v("phase", phase,
    "two-phase lbm: the fluid that enters through this pressure or velocity face, red or blue (drainage, "
    "imbibition); omitted: what enters takes the colour of the face's cell, as at an outlet",
    config::one_of({"", "red", "blue"}));
  v("profile", profile,
    "velocity faces: uniform, or parabolic: the value at the face's centre, falling as 4 s (1 - s) to zero "
    "at "
    "the faces across each of its other axes that is not periodic (a channel's or, as a product, a duct's "
    "inlet), table (profile_file) or expression (profile_expression); fv takes the factor at its face's "
    "points, lbm at its face nodes, the centres of the cells on the face (s = (i + 1/2) / cells; a formula "
    "there, h/2 inside the box)",
    config::one_of({"uniform", "parabolic", "table", "expression"}));
  v("profile_file", profile_file,
    "profile: table: a text file of rows `coordinate, factor`, the coordinate in m along profile_axis and "
    "the "
    "factor on `value` there; linear between rows, the end rows' factor beyond them; relative to this file");
  v("profile_axis", profile_axis,
    "profile: table, and turbulence_file: the axis of the tables' coordinate, across the face",
    config::one_of({"x", "y", "z"}));
  v("profile_expression", profile_expression,
    "profile: expression: the factor on `value` as a formula in x, y, z (m, the point on the face; lbm: its "
    "node) and "
    "t "
    "(s), e.g. `4*y*(1-y)` or `cos(2*pi*t/0.5)`; constants pi and e, muParser's functions (sin, cos, exp, "
    "sqrt, abs, min, max, ...) and `c ? a : b`; quote it in YAML; lbm evaluates t at each step's end");
  v("k", k,
    "velocity faces with fluid.turbulence (fv): k of the fluid entering here, m^2/s^2, with epsilon; 0: "
    "turbulence.inlet's",
    config::at_least(0.0));
  v("epsilon", epsilon,
    "velocity faces with fluid.turbulence (fv): the dissipation rate of the fluid entering here, m^2/s^3, "
    "with k; "
    "0: turbulence.inlet's",
    config::at_least(0.0));
  v("intensity", intensity,
    "velocity faces with fluid.turbulence (fv), instead of k and epsilon: the turbulence intensity I of the "
    "fluid entering here (r.m.s. fluctuation over speed, e.g. 0.05), with mixing_length; k = 3/2 (I |u|)^2 "
    "with |u| the inlet's local speed (its profile and ramp included)",
    config::at_least(0.0));
  v("mixing_length", mixing_length,
    "with intensity: the mixing length L of the fluid entering here, m (e.g. 0.07 of a duct's hydraulic "
    "diameter); epsilon = C_mu^(3/4) k^(3/2) / L",
    config::at_least(0.0));
  v("turbulence_file", turbulence_file,
    "velocity faces with fluid.turbulence (fv), instead of k and epsilon: a text file of rows `coordinate, "
    "k, "
    "epsilon` (m along profile_axis, m^2/s^2, m^2/s^3; k >= 0, epsilon > 0), what enters here across the "
    "face (a "
    "precursor run's profiles); linear between rows, the end rows' values beyond them; relative to this "
    "file");
  if (!v.reading()) return;
  check_profile_keys(v);
  check_inlet_turbulence_keys(v);
  const bool given = v.given("value");
  if (profile != "uniform" && type != "velocity")
    v.fail("profile", fmt::format("a {} boundary has no velocity profile; profile is for velocity faces", type));
  if (!phase.empty() && type != "pressure" && type != "velocity")
    v.fail("phase", fmt::format("a {} boundary lets nothing of a chosen colour in; phase is for pressure and velocity "
                                "faces",
                                type));
  const bool valueless = type == "wall" || type == "outflow" || type == "symmetry";
  if (valueless && closure != "auto")
    v.fail("closure", fmt::format("a {} boundary has no closure to choose", type));
  if (closure == "auto") closure = type == "pressure" ? "regularized" : type == "velocity" ? "zou-he" : "auto";
  if (type == "pressure" && (!given || value.values.size() != 1))
    v.fail(given ? "value" : "", "a pressure boundary needs one number, e.g. value: 0.0 (Pa)");
  if (type == "velocity" && (!given || value.values.size() != 3))
    v.fail(given ? "value" : "", "a velocity boundary needs three numbers, e.g. value: [0.1, 0, 0] (m/s)");
  if (valueless && ramp > 0.0)
    v.fail("ramp", fmt::format("a {} boundary has no value to ramp", type));
  if (valueless && given)
    v.fail("value", fmt::format("a {} boundary takes no value; for a moving wall use type: velocity", type));
}

// profile_file with profile: table, profile_expression with profile:
// expression; reads the table or parses the formula.
void BoundaryParams::check_profile_keys(config::Visitor& v) {
  if (profile == "table" && profile_file.empty())
    v.fail("profile", "a table profile needs profile_file: the file of its rows (coordinate, factor)");
  if (profile != "table" && !profile_file.empty())
    v.fail("profile_file", "profile_file is read for profile: table only; add profile: table or remove it");
  if (profile == "table" && !profile_file.empty()) {
    try {
      table = read_profile_table(profile_file.path, profile_axis[0] - 'x');
    } catch (const std::exception& e) {
      v.fail("profile_file", e.what());
    }
  }
  if (profile == "expression" && profile_expression.empty())
    v.fail("profile",
           "an expression profile needs profile_expression: the factor as a formula, e.g. \"4*y*(1-y)\"");
  if (profile != "expression" && !profile_expression.empty())
    v.fail("profile_expression",
           "profile_expression is read for profile: expression only; add profile: expression "
           "or remove it");
  if (profile == "expression" && !profile_expression.empty()) {
    try {
      formula = ProfileExpression(profile_expression);
    } catch (const std::exception& e) {
      v.fail("profile_expression", e.what());
    }
  }
}

// k and epsilon, or intensity and mixing_length, in pairs, on velocity faces only.
void BoundaryParams::check_inlet_turbulence_keys(config::Visitor& v) {
  if ((k > 0.0) != (epsilon > 0.0))
    v.fail(k > 0.0 ? "k" : "epsilon",
           fmt::format("{} is given without {} (0 means turbulence.inlet's): give both above 0, or neither",
                       k > 0.0 ? "k" : "epsilon", k > 0.0 ? "epsilon" : "k"));
  if ((intensity > 0.0) != (mixing_length > 0.0))
    v.fail(intensity > 0.0 ? "intensity" : "mixing_length",
           fmt::format("{} is given without {}: give both above 0 (k and epsilon then follow the inlet's "
                       "speed), or neither",
                       intensity > 0.0 ? "intensity" : "mixing_length",
                       intensity > 0.0 ? "mixing_length" : "intensity"));
  if (intensity > 0.0 && k > 0.0)
    v.fail("intensity",
           "k and epsilon are given twice, as values and by intensity and mixing_length: keep one "
           "pair");
  const bool tabled = !turbulence_file.empty();
  if (tabled && (k > 0.0 || intensity > 0.0)) {
    v.fail("turbulence_file",
           fmt::format("k and epsilon are given twice: in turbulence_file and as {}; keep one",
                       k > 0.0 ? "k and epsilon" : "intensity and mixing_length"));
    return;
  }
  const char* key = k > 0.0 ? "k" : intensity > 0.0 ? "intensity" : tabled ? "turbulence_file" : nullptr;
  if (key && type != "velocity") {
    v.fail(key, fmt::format("{} are given on velocity faces (inlets) only; this {} face takes k and epsilon "
                            "from the flow: remove them here",
                            k > 0.0           ? "k and epsilon"
                            : intensity > 0.0 ? "intensity and mixing_length"
                                              : "tables of k and epsilon",
                            type));
    return;
  }
  if (!tabled) return;
  try {
    const auto t = read_profile_columns(turbulence_file.path, profile_axis[0] - 'x', {"k", "epsilon"});
    k_table = t[0], epsilon_table = t[1];
  } catch (const std::exception& e) {
    v.fail("turbulence_file", e.what());
    return;
  }
  for (std::size_t r = 0; r < k_table.at.size(); ++r)
    if (!(k_table.factor[r] >= 0.0 && epsilon_table.factor[r] > 0.0)) {
      v.fail(
          "turbulence_file",
          fmt::format("k {} and epsilon {} in data row {} (headers, comments and blank lines not counted): k "
                      "must be 0 or more and epsilon above 0 ({})",
                      k_table.factor[r], epsilon_table.factor[r], r + 1, turbulence_file.path));
      return;
    }
}

std::array<double, 2> FluidParams::FaceTurbulence::at(int f, double speed, const double x[3]) const {
  const auto i = static_cast<std::size_t>(f);
  if (from_table(f)) {
    const int a = k_table[i].axis;
    return {k_table[i](x[a]), epsilon_table[i](x[a])};
  }
  if (!from_speed(f)) return {k[i], epsilon[i]};
  const double fluctuation = intensity[i] * speed, kf = 1.5 * fluctuation * fluctuation;
  return {kf, std::pow(c_mu, 0.75) * kf * std::sqrt(kf) / length[i]};
}

// An expression profile gives a number at the face's centre, corners and
// edge midpoints at t = 0 (else the run would stop at its first step).
static void check_profile_on_face(config::Visitor& v, const config::Config& cfg, const BoundaryParams& b,
                                  int face) {
  const int a = face / 2;
  const int u = (a + 1) % 3, w = (a + 2) % 3;
  for (double su : {0.0, 0.5, 1.0})
    for (double sw : {0.0, 0.5, 1.0}) {
      double s[3];
      s[a] = face % 2, s[u] = su, s[w] = sw;
      try {
        b.profile_factor(face, s, cfg, 0.0);
      } catch (const std::exception& e) {
        v.fail("profile_expression", e.what());
        return;
      }
    }
}

void FluidParams::visit(config::Visitor& v, const config::Config& cfg) {
  v.required("density", density, "fluid density, kg/m^3", config::positive());
  v.required("viscosity", viscosity, "kinematic viscosity, m^2/s", config::positive());
  v("body_force", body_force, "body force density, N/m^3 (e.g. to drive periodic flow)");
  std::vector<std::string> faces_open;
  v.entries(
      "boundaries", "boundary per face (x-, x+, y-, y+, z-, z+); periodic faces are omitted",
      [&](const std::string& face, config::Visitor& s) {
        boundaries[face].visit(s);
        if (s.reading()) {
          const int axis = face[0] - 'x';
          if (cfg.domain.periodic[axis])
            s.fail("", fmt::format("face {} is periodic (domain.periodic[{}] is true): remove this "
                                   "boundary or make the axis non-periodic",
                                   face, axis));
          if (cfg.domain.cells[axis] == 1)
            s.fail("", fmt::format("axis {} has one cell (a 2D run): it takes no boundary", "xyz"[axis]));
          const auto& b = boundaries[face];
          const bool tables = b.profile == "table" || !b.turbulence_file.empty();
          const int across = b.profile_axis[0] - 'x';
          if (tables && across == axis)
            s.fail("profile_axis", fmt::format("the table's axis {} is the face's normal; give an axis across "
                                               "the face",
                                               b.profile_axis));
          else if (tables && cfg.domain.cells[across] == 1)
            s.fail("profile_axis",
                   fmt::format("the table's axis {} has one cell (a 2D run): give an axis across "
                               "the face that has more",
                               b.profile_axis));
          if (!b.formula.empty()) check_profile_on_face(s, cfg, b, 2 * axis + (face[1] == '+' ? 1 : 0));
        }
      },
      face_names());
  v.section("initial", "initial state", [&](config::Visitor& s) {
    s("field", initial_field,
      "uniform (velocity, pressure), or added to them in x-y: a taylor-green vortex (periodic in the box) or a "
      "vortex: a shielded (Gaussian) vortex, u_theta = amplitude (r / radius) exp((1 - r^2 / radius^2) / 2), its "
      "peak at r = radius, no net circulation (a disturbance to carry through open faces)",
      config::one_of({"uniform", "taylor-green", "vortex"}));
    s("center", initial_center, "vortex: [x, y] of its centre, m");
    s("radius", initial_radius, "vortex: radius of its peak swirl, m", config::at_least(0.0));
    if (s.reading() && initial_field == "vortex" && (initial_center.values.size() < 2 || !(initial_radius > 0)))
      s.fail("field", "a vortex needs center: [x, y] and radius > 0");
    s("velocity", initial_velocity, "initial velocity, m/s");
    s("pressure", initial_pressure, "initial pressure, Pa");
    s("amplitude", initial_amplitude, "taylor-green: velocity amplitude U0; vortex: peak swirl, m/s");
    visit_phase_regions(s, cfg, initial_phase);
    if (s.reading() && !initial_phase.empty() && !v.given("two_phase"))
      s.fail("phase", "painting phases needs a two-phase fluid: add fluid.two_phase (surface_tension, ...)");
  });
  v.section(
      "two_phase",
      "two immiscible fluids of equal density by the colour-gradient lattice Boltzmann model (Rothman-Keller, with "
      "the recolouring of Latva-Kokko & Rothman 2005); omit for one fluid",
      [&](config::Visitor& s) {
        if (!s.reading() || two_phase.on) two_phase.visit(s);
      },
      &two_phase.on);
  v.section(
      "turbulence",
      "fv: the Reynolds-averaged closure, k-epsilon with the two-layer wall model (seed 003 §3.1.2) or wall "
      "functions; omit for laminar flow",
      [&](config::Visitor& s) {
        if (!s.reading() || turbulence.on) turbulence.visit(s);
      },
      &turbulence.on);
  visit_solids(v, cfg, solids);
  if (!v.reading()) return;
  check_solids(v, cfg);
  for (int f = 0; f < 6; ++f) {
    const auto it = boundaries.find(face_names()[f]);
    if (it != boundaries.end() && !it->second.phase.empty() && !two_phase.on)
      v.fail("boundaries", fmt::format("face {} gives a phase, but the fluid is one: add fluid.two_phase, or "
                                       "leave phase out",
                                       face_names()[f]));
  }
  if (two_phase.on && two_phase.viscosity_blue == 0.0) two_phase.viscosity_blue = viscosity;
}

// What fluid.solids needs of the rest: at most 254 solids; a contact angle
// only for two fluids; fluid in the first two layers of every open face (its
// closure reads the cell next in).
void FluidParams::check_solids(config::Visitor& v, const config::Config& cfg) const {
  if (solids.empty()) return;
  if (solids.size() > 254)
    v.fail("solids", fmt::format("{} solids; at most 254 (merge voxel images into one)", solids.size()));
  for (std::size_t n = 0; n < solids.size(); ++n)
    if (solids[n].contact_angle != -1.0 && !two_phase.on)
      v.fail("solids", fmt::format("solids[{}] gives a contact angle, but the fluid is one: add fluid.two_phase, "
                                   "or leave contact_angle out",
                                   n));
  std::vector<int> open;
  for (int f = 0; f < 6; ++f) {
    const std::string t = boundary(f, cfg).type;
    if ((t == "pressure" || t == "velocity" || t == "outflow") && cfg.domain.cells[f / 2] > 1) open.push_back(f);
  }
  if (open.empty() || solids.size() > 254) return;
  std::vector<std::uint8_t> map;
  try {
    map = solid_map(cfg, solids);
  } catch (const std::runtime_error&) {
    return;  // the item's own check has said what is wrong
  }
  const auto& n = cfg.domain.cells;
  for (int f : open)
    for (long k = 0; k < n[2]; ++k)
      for (long j = 0; j < n[1]; ++j)
        for (long i = 0; i < n[0]; ++i) {
          const long at[3] = {i, j, k}, a = f / 2, layer = f % 2 == 0 ? at[a] : n[a] - 1 - at[a];
          if (layer > 1 || !map[static_cast<std::size_t>((k * n[1] + j) * n[0] + i)]) continue;
          v.fail("solids", fmt::format("a solid reaches cell ({}, {}, {}), within two cells of the open face {}: "
                                       "its closure needs fluid there; move the solid inwards or lengthen the "
                                       "domain",
                                       i, j, k, face_names()[f]));
          return;
        }
}

void FluidParams::initial_state(const config::Config& cfg, const Vec3& x, Vec3& u, double& p) const {
  u = initial_velocity;
  p = initial_pressure;
  if (initial_field == "vortex") {  // the pressure follows from the first projection
    const double dx = x[0] - initial_center.values.at(0), dy = x[1] - initial_center.values.at(1);
    const double r2 = (dx * dx + dy * dy) / (initial_radius * initial_radius);
    const double swirl = initial_amplitude * std::exp(0.5 * (1 - r2)) / initial_radius;  // u_theta / r
    u[0] -= swirl * dy;
    u[1] += swirl * dx;
    return;
  }
  if (initial_field != "taylor-green") return;
  // u = U0 (sin kx x cos ky y, -(kx/ky) cos kx x sin ky y), periodic in the box.
  const auto& d = cfg.domain;
  const double kx = 2 * std::numbers::pi / (d.upper[0] - d.lower[0]);
  const double ky = 2 * std::numbers::pi / (d.upper[1] - d.lower[1]);
  const double X = kx * (x[0] - d.lower[0]), Y = ky * (x[1] - d.lower[1]), U = initial_amplitude;
  u[0] += U * std::sin(X) * std::cos(Y);
  u[1] -= U * (kx / ky) * std::cos(X) * std::sin(Y);
  p += 0.25 * density * U * U * (std::cos(2 * X) + (kx * kx) / (ky * ky) * std::cos(2 * Y));
}

double ProfileTable::operator()(double coordinate) const {
  if (coordinate <= at.front()) return factor.front();
  if (coordinate >= at.back()) return factor.back();
  const auto k = static_cast<std::size_t>(std::upper_bound(at.begin(), at.end(), coordinate) - at.begin());
  const double t = (coordinate - at[k - 1]) / (at[k] - at[k - 1]);
  return factor[k - 1] + t * (factor[k] - factor[k - 1]);
}

ProfileTable read_profile_table(const std::string& path, int axis) {
  return read_profile_columns(path, axis, {"factor"}).front();
}

// One row: the coordinate and one number per column, or nothing (blank, a
// comment) when `row` holds no non-blank character; false when it is not that.
static bool read_row(std::string line, double& x, std::vector<double>& values, bool& blank) {
  line = line.substr(0, line.find('#'));
  std::replace(line.begin(), line.end(), ',', ' ');
  blank = line.find_first_not_of(" \t\r") == std::string::npos;
  if (blank) return true;
  std::istringstream row(line);
  std::string rest;
  if (!(row >> x)) return false;
  for (double& v : values)
    if (!(row >> v)) return false;
  return !(row >> rest);
}

std::vector<ProfileTable> read_profile_columns(const std::string& path, int axis,
                                               const std::vector<std::string>& names) {
  if (const std::string why = config::file_problem(path); !why.empty())
    throw std::runtime_error(fmt::format("the profile table {}: {}", path, why));
  std::ifstream in(path);
  if (!in) throw std::runtime_error(fmt::format("cannot open the profile table {}", path));
  std::vector<ProfileTable> t(names.size());
  for (auto& c : t) c.axis = axis;
  static const char* counts[] = {"one", "two", "three", "four", "five"};
  std::string line, listed = names.back();
  for (std::size_t c = names.size() - 1; c-- > 0;)
    listed = names[c] + (c + 2 == names.size() ? " and " : ", ") + listed;
  bool header = false;
  std::vector<double> values(names.size());
  for (int n = 1; std::getline(in, line); ++n) {
    double x = 0.0;
    bool blank = false;
    if (!read_row(line, x, values, blank)) {
      if (t[0].at.empty() && !header) {  // a header
        header = true;
        continue;
      }
      throw std::runtime_error(fmt::format("a row must be {} numbers, coordinate{} {} (line {} of {})",
                                           counts[std::min<std::size_t>(names.size(), 4)],
                                           names.size() == 1 ? " and" : ",", listed, n, path));
    }
    if (blank) continue;
    if (!t[0].at.empty() && !(x > t[0].at.back()))
      throw std::runtime_error(fmt::format("the coordinates must increase row to row (line {} of {})", n, path));
    for (std::size_t c = 0; c < names.size(); ++c) {
      if (!std::isfinite(values[c]))
        throw std::runtime_error(fmt::format("the {} is not a number (line {} of {})", names[c], n, path));
      t[c].at.push_back(x);
      t[c].factor.push_back(values[c]);
    }
  }
  if (t[0].at.size() < 2)
    throw std::runtime_error(fmt::format("a profile table needs two rows at least ({})", path));
  return t;
}

double BoundaryParams::profile_factor(int face, const double s[3], const config::Config& cfg,
                                      double t) const {
  const auto& d = cfg.domain;
  if (profile == "expression") {  // at the point's place across the face, on the face along its normal
    // Ghost lines beyond the other faces ask too (their values are replaced by
    // those faces' conditions): they take the formula on the box's edge, so
    // that one valid inside (sqrt(y), y^(1/7)) is not evaluated outside it.
    double x[3];
    for (int a = 0; a < 3; ++a)
      x[a] = d.lower[a] + (d.periodic[a] ? s[a] : std::clamp(s[a], 0.0, 1.0)) * (d.upper[a] - d.lower[a]);
    x[face / 2] = face % 2 == 0 ? d.lower[face / 2] : d.upper[face / 2];
    return formula(x, t);
  }
  // The table and the parabola, too, on the box's edge for the ghost lines
  // beyond the other faces (the parabola went negative there).
  const auto inside = [&](int a) { return d.periodic[a] ? s[a] : std::clamp(s[a], 0.0, 1.0); };
  if (profile == "table") {
    const int a = table.axis;
    return table(cfg.domain.lower[a] + inside(a) * (cfg.domain.upper[a] - cfg.domain.lower[a]));
  }
  if (profile != "parabolic") return 1.0;
  double f = 1.0;
  for (int a = 0; a < 3; ++a)
    if (a != face / 2 && !cfg.domain.periodic[a] && cfg.domain.cells[a] > 1)
      f *= 4 * inside(a) * (1 - inside(a));
  return f;
}

FluidParams::FaceTurbulence FluidParams::inlet_turbulence(const config::Config& cfg) const {
  FaceTurbulence t;
  t.c_mu = turbulence.constants.C_mu;
  for (int f = 0; f < 6; ++f) {
    const BoundaryParams b = boundary(f, cfg);
    const auto i = static_cast<std::size_t>(f);
    const bool own = b.k > 0.0, varies = b.intensity > 0.0 || b.k_table.axis >= 0;
    t.k[i] = own ? b.k : varies ? 0.0 : turbulence.inlet_k;
    t.epsilon[i] = own ? b.epsilon : varies ? 0.0 : turbulence.inlet_epsilon;
    t.intensity[i] = b.intensity;
    t.length[i] = b.mixing_length;
    t.k_table[i] = b.k_table;
    t.epsilon_table[i] = b.epsilon_table;
  }
  return t;
}

BoundaryParams FluidParams::boundary(int face, const config::Config& cfg) const {
  const int axis = face / 2;
  if (cfg.domain.periodic[axis]) {
    BoundaryParams periodic;
    periodic.type = "periodic";
    return periodic;
  }
  auto it = boundaries.find(face_names()[face]);
  return it == boundaries.end() ? BoundaryParams{} : it->second;
}

}  // namespace coflow::fluid
