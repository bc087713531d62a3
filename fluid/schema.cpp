#include "fluid/schema.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "coflow/clock.hpp"
#include "coflow/decomposition.hpp"
#include "fluid/analytic/params.hpp"
#include "fluid/fv/params.hpp"
#include "fluid/lbm/params.hpp"
#include "fluid/lbm/units.hpp"
#include "fluid/params.hpp"

namespace coflow::fluid {

const std::vector<VariantSchema>& variant_schemas() {
  static const std::vector<VariantSchema> v{
      variant_schema<lbm::LbmParams>(
          "lbm",
          "lattice Boltzmann, D2Q9/D3Q19, BGK or TRT, standard or He-Luo incompressible, regularized and "
          "Zou-He faces, MPI",
          "lbm"),
      variant_schema<lbm::LbmParams>(
          "lbm-reference", "plain serial lattice Boltzmann (the oracle for lbm): same physics, simplest code",
          "lbm"),
      variant_schema<AnalyticParams>("analytic",
                                     "prescribed fields (quiescent, uniform, poiseuille, taylor-green, "
                                     "grid-turbulence), exact at any time",
                                     "analytic"),
      variant_schema<fv::FvParams>(
          "fv",
          "finite volumes on a staggered grid, projection, IMEX SBDF2/CNAB2 with a CFL step, the pressure by "
          "coflow's geometric multigrid (hypre PFMG/SMG where it does not suit), MPI (seed 003 §4.1)",
          "fv"),
      variant_schema<fv::FvParams>(
          "fv-reference",
          "plain serial finite volumes (the oracle for fv): same discretisation, simple loops, "
          "unpreconditioned conjugate gradients",
          "fv"),
  };
  return v;
}

namespace {

// fluid.turbulence is given (the resolved file names its model).
bool turbulent(const config::Config& cfg) {
  return !config::resolved_text(cfg, {"fluid", "turbulence", "model"}).empty();
}

// fluid.fv.refinement is given.
bool refined(const config::Config& cfg) { return config::resolved_node(cfg, "fluid.fv.refinement").IsMap(); }

// lbm takes the solids of psm and returns the force on them (with two fluids
// it also takes their wetting: immersed's contract); analytic is a
// prescribed flow (with turbulence) that nothing feeds back into.
config::Contract contract(const config::Config& cfg, const std::string& variant) {
  namespace f = config::fields;
  config::Contract c;
  if (variant == "lbm" || variant == "lbm-reference") c.provides = {f::velocity, f::pressure, f::solid_force};
  if (variant == "analytic") c.provides = {f::velocity, f::pressure, f::k, f::epsilon};
  if (variant == "fv" || variant == "fv-reference") c.provides = {f::velocity, f::pressure};
  if ((variant == "fv" || variant == "fv-reference") && turbulent(cfg))
    c.provides = {f::velocity, f::pressure, f::k, f::epsilon};
  if (variant == "fv" || variant == "fv-reference") c.provides.push_back(f::ibm_forcing);
  // lbm and lbm-reference force immersed boundaries with one fluid or two
  // (not beside interior solids: check_lbm_solids).
  if (variant == "lbm" || variant == "lbm-reference") c.provides.push_back(f::ibm_forcing);
  return c;
}

// The snapshot fields each variant writes (LbmSolver/LbmReference/AnalyticFluid::fields).
std::vector<std::string> writes(const std::string& variant) {
  if (variant == "lbm" || variant == "lbm-reference")
    return {"velocity", "pressure", "density", "solid_fraction", "phase"};
  if (variant == "analytic") return {"velocity", "pressure", "density", "vorticity", "k", "epsilon"};
  if (variant == "fv" || variant == "fv-reference")
    return {"velocity", "pressure", "density", "divergence", "k", "epsilon", "nu_t", "y_plus"};
  return {};  // external: its own business
}

// One subsection per variant family; only the chosen one may be given.
void visit_variant_sections(config::Visitor& v, const config::Config& cfg, const config::ComponentInfo& info) {
  std::vector<std::string> done;
  for (const auto& e : variant_schemas()) {
    if (e.params_section.empty() || std::find(done.begin(), done.end(), e.params_section) != done.end()) continue;
    const VariantSchema* chosen = &e;
    if (v.reading()) {
      chosen = &find_variant(variant_schemas(), info.variant);
      if (chosen->params_section != e.params_section) chosen = nullptr;
    }
    if (chosen) {
      done.push_back(e.params_section);
      v.section(e.params_section, fmt::format("parameters of solver {}", e.name),
                [&](config::Visitor& sub) { chosen->visit(sub, v.reading() ? &cfg : nullptr); });
    } else if (v.given(e.params_section)) {
      // Said once per section (lbm and lbm-reference share one), and its keys
      // are not reported again as unknown.
      done.push_back(e.params_section);
      v.fail(e.params_section, fmt::format("only used with solver: {} (this run uses solver: {}); "
                                           "remove the section or change the solver",
                                           e.name, info.variant));
      v.section(e.params_section, "", [](config::Visitor& sub) { sub.accept_other_keys(); });
    }
  }
}

// A face of a non-periodic axis (of more than one cell) that the file leaves out
// is a wall (FluidParams::boundary): the resolved file says so.
void resolve(config::Config& cfg, const std::string& variant) {
  if (variant == "external" || variant == "analytic")
    return;  // analytic takes no boundaries (check_analytic_keys)
  const auto& d = cfg.domain;
  for (int f = 0; f < 6; ++f) {
    const int axis = f / 2;
    if (d.periodic[axis] || d.cells[axis] == 1) continue;
    YAML::Node b = cfg.resolved["fluid"]["boundaries"][face_names()[f]];
    if (b.IsDefined() && !b.IsNull()) continue;
    b["type"] = "wall";
    b["ramp"] = 0;
    b["closure"] = "auto";
  }
}

}  // namespace

// The fluid's blocks as the run will cut them; false when fluid.ranks or
// fluid.decomposition cannot be cut (reported there).
static bool fluid_blocks(const config::Config& cfg, const config::ComponentInfo& info, coupler::Decomposition& dec) {
  const auto& d = cfg.domain;
  std::array<int, 3> dims{0, 0, 0};
  if (!info.decomposition.is_auto) dims = info.decomposition.value;
  try {
    dec = coupler::Decomposition({d.cells[0], d.cells[1], d.cells[2]}, info.ranks, dims, d.periodic);
  } catch (const std::invalid_argument&) {
    return false;
  }
  return true;
}

// An outflow face, a regularized pressure face, and a pressure or velocity
// face that meets another one (its edge nodes are rebuilt from the next
// cell in: lbm/boundaries.hpp, close_corner) read the next cell in, but the
// halo carries only the populations that stream inwards: lbm's block at such
// a face must be two cells thick or more along the face's axis.
static void check_open_face_blocks(config::Visitor& v, const config::Config& cfg, const config::ComponentInfo& info,
                            const FluidParams& p) {
  if (!v.reading() || info.variant.rfind("lbm", 0) != 0 || info.ranks < 2) return;
  const auto& d = cfg.domain;
  coupler::Decomposition dec;
  if (!fluid_blocks(cfg, info, dec)) return;  // reported at fluid.ranks already
  for (int f = 0; f < 6; ++f) {
    const BoundaryParams b = p.boundary(f, cfg);
    const int a = f / 2;
    const auto pv = [&](int g) {
      const std::string t = p.boundary(g, cfg).type;
      return d.cells[g / 2] > 1 && !d.periodic[g / 2] && (t == "pressure" || t == "velocity");
    };
    bool meets = false;
    for (int g = 0; g < 6; ++g) meets = meets || (g / 2 != a && pv(f) && pv(g));
    if ((b.type != "outflow" && !(b.type == "pressure" && b.closure == "regularized") && !meets) ||
        d.cells[a] == 1)
      continue;
    for (int r = 0; r < info.ranks; ++r) {
      const auto& blk = dec.block(r);
      if ((f % 2 == 0 ? blk.lo[a] != 0 : blk.hi[a] != d.cells[a]) || blk.hi[a] - blk.lo[a] >= 2) continue;
      v.fail("ranks", fmt::format("the {} blocks leave the one at face {} ({} face) one cell thick along {}, but "
                                  "the face reads the next cell in; use fewer blocks along {} (fluid.decomposition) "
                                  "or fewer ranks",
                                  info.ranks, face_names()[f], b.type, "xyz"[a], "xyz"[a]));
      return;
    }
  }
}

// fv's ghost layers are two cells wide (the upwind-biased face value reads
// two cells upstream), and an open face or a wall reads the second cell in:
// every block must be two cells thick along every axis of more than one cell.
static void check_fv_blocks(config::Visitor& v, const config::Config& cfg, const config::ComponentInfo& info) {
  if (!v.reading() || info.variant.rfind("fv", 0) != 0) return;
  if (info.variant == "fv-reference" && info.ranks != 1) return;  // serial: visit_component_common says so
  const auto& d = cfg.domain;
  coupler::Decomposition dec;
  if (!fluid_blocks(cfg, info, dec)) return;  // reported at fluid.ranks already
  for (int r = 0; r < info.ranks; ++r)
    for (int a = 0; a < 3; ++a)
      if (d.cells[a] > 1 && dec.block(r).extent(a) < 2) {
        v.fail("ranks", fmt::format("{} blocks make block {} one cell thick along {}; fv needs two (its ghost "
                                    "layers are two wide): use fewer blocks along {} (fluid.decomposition) or fewer "
                                    "ranks",
                                    info.ranks, r, "xyz"[a], "xyz"[a]));
        return;
      }
}

// A velocity face's normal component as given (0 for other faces).
static double normal_velocity(const BoundaryParams& b, int face) {
  return b.type == "velocity" && b.value.values.size() == 3
             ? b.value.values[static_cast<std::size_t>(face / 2)]
             : 0.0;
}

// fv: the uniform velocity faces of a closed box (check_closed_box) must let
// in what they let out, at every time: the same net flux to round-off and the
// same ramp (fv stopped at its first projection otherwise). Profiled faces are
// left to the run.
static void check_velocity_faces_balance(config::Visitor& v, const config::Config& cfg,
                                         const FluidParams& p) {
  double in = 0.0, out = 0.0, speed = 0.0;
  std::map<double, double> net_by_ramp;  // faces that ramp together must balance together
  const auto& d = cfg.domain;
  const auto h = d.spacing();
  for (int f = 0; f < 6; ++f) {
    const int a = f / 2;
    if (d.cells[a] == 1 || d.periodic[a]) continue;
    const BoundaryParams b = p.boundary(f, cfg);
    for (double x : b.type == "velocity" ? b.value.values : std::vector<double>{})
      speed = std::max(speed, std::abs(x));
    const double normal = normal_velocity(b, f);
    if (normal == 0.0) continue;
    if (b.profile != "uniform") return;
    double area = 1.0;
    for (int o = 0; o < 3; ++o)
      if (o != a) area *= d.upper[o] - d.lower[o];
    const double q = (f % 2 == 0 ? normal : -normal) * area;  // into the box
    (q > 0 ? in : out) += std::abs(q);
    net_by_ramp[b.ramp] += q;
  }
  // fv's own test (fv::check_closed_balance): a mean divergence above 1e-12
  // U / h is no round-off.
  const double volume = (d.upper[0] - d.lower[0]) * (d.upper[1] - d.lower[1]) * (d.upper[2] - d.lower[2]);
  const double hmin = std::min({h[0], h[1], d.cells[2] == 1 ? h[0] : h[2]});
  const double tolerance = 1e-12 * speed / hmin * volume;
  bool ramps_unbalanced = false;
  for (const auto& [ramp, net] : net_by_ramp)
    ramps_unbalanced = ramps_unbalanced || std::abs(net) > tolerance;
  if (std::abs(in - out) > tolerance)
    v.fail("boundaries",
           fmt::format("the velocity faces let in {} m^3/s and let out {} m^3/s: an incompressible "
                       "fluid in a closed box needs the two equal; balance them, or make a face "
                       "pressure or outflow",
                       config::number(in), config::number(out)));
  else if (ramps_unbalanced)
    v.fail("boundaries",
           "the velocity faces that let fluid through ramp over different times, so they do not "
           "balance while they ramp: give the faces that balance each other the same ramp, or make a face "
           "pressure or outflow");
}

// fv: a box whose faces let fluid through only at velocity faces must balance
// them; a single such face cannot (the projection, which takes the
// right-hand side's mean out as round-off, would spread its flux over every
// cell as a divergence; fv checks the balance as it runs, too).
static void check_closed_box(config::Visitor& v, const config::Config& cfg, const config::ComponentInfo& info,
                             const FluidParams& p) {
  if (!v.reading() || info.variant.rfind("fv", 0) != 0) return;
  int through = -1, count = 0;
  for (int f = 0; f < 6; ++f) {
    if (cfg.domain.cells[f / 2] == 1 || cfg.domain.periodic[f / 2]) continue;
    const BoundaryParams b = p.boundary(f, cfg);
    if (b.type == "pressure" || b.type == "outflow") return;
    const double normal = normal_velocity(b, f);
    if (b.type == "velocity" && (b.profile == "expression" || b.profile == "table"))
      return;  // fv's run checks its flux
    if (normal != 0.0) ++count, through = f;
  }
  if (count == 1)
    v.fail(
        "boundaries." + face_names()[through],
        fmt::format(
            "the velocity face {} lets fluid through, and no other face lets it {}: an incompressible "
            "fluid cannot fill or empty a closed box; make a face where it leaves or enters pressure or "
            "outflow",
            face_names()[through],
            (through % 2 == 0) == (normal_velocity(p.boundary(through, cfg), through) > 0) ? "out" : "in"));
  if (count > 1) check_velocity_faces_balance(v, cfg, p);
}

// D2Q9 has no velocities along z: a z body force, initial velocity or
// velocity face would enter its equilibria (u^2, u.F) and show in the output
// without moving anything. D3Q19 with one periodic cell along z carries them.
static void check_lbm_planar(config::Visitor& v, const config::Config& cfg, const std::string& variant) {
  if (variant.rfind("lbm", 0) != 0 || config::resolved_text(cfg, {"fluid", "lbm", "lattice"}) != "D2Q9")
    return;
  FluidParams p;
  config::Reader r(cfg.resolved["fluid"], cfg.file, "fluid");
  p.visit(r, cfg);  // the resolved file: its own problems were reported by the visit
  const char* fix =
      "D2Q9 has no velocities along z: set it to 0, or take lattice D3Q19 with one periodic cell "
      "along z, which carries a flow across the plane";
  if (p.body_force[2] != 0.0)
    v.fail("fluid.body_force", fmt::format("body_force[2] is {:g} N/m^3: {}", p.body_force[2], fix));
  if (p.initial_velocity[2] != 0.0)
    v.fail("fluid.initial.velocity", fmt::format("velocity[2] is {:g} m/s: {}", p.initial_velocity[2], fix));
  for (const auto& [face, b] : p.boundaries)
    if (b.type == "velocity" && b.value.values.size() == 3 && b.value.values[2] != 0.0)
      v.fail("fluid.boundaries." + face + ".value",
             fmt::format("value[2] is {:g} m/s: {}", b.value.values[2], fix));
}

// The key that gives a face's own inlet k and epsilon (null: none), and what it gives.
static std::pair<const char*, const char*> inlet_turbulence_key(const BoundaryParams& b) {
  if (b.k > 0.0) return {"k", "k and epsilon"};
  if (b.intensity > 0.0) return {"intensity", "intensity and mixing_length"};
  if (!b.turbulence_file.empty()) return {"turbulence_file", "tables of k and epsilon"};
  return {nullptr, nullptr};
}

// k-epsilon runs on fv and fv-reference; without a wall model
// the box has no walls; fluid entering through a velocity face brings its k
// and epsilon.
static void check_turbulence(config::Visitor& v, const config::Config& cfg, const config::ComponentInfo& info,
                             const FluidParams& p) {
  if (!v.reading()) return;
  for (int f = 0; f < 6; ++f) {
    const auto [key, what] = inlet_turbulence_key(p.boundary(f, cfg));
    if (!p.turbulence.on && key)
      v.fail("boundaries." + face_names()[f] + "." + key,
             fmt::format(
                 "{} of a face are for the k-epsilon model: add fluid.turbulence (solver fv) or remove them",
                 what));
  }
  if (!p.turbulence.on) return;
  if (info.variant.rfind("fv", 0) != 0) {
    v.fail("turbulence", fmt::format("solver {} has no turbulence model; k-epsilon runs on solver: fv", info.variant));
    return;
  }
  for (int f = 0; f < 6; ++f) {
    if (cfg.domain.cells[f / 2] == 1) continue;
    const BoundaryParams b = p.boundary(f, cfg);
    const double normal = normal_velocity(b, f);
    // A velocity face that lets nothing through is a (moving) wall to fv.
    if ((b.type == "wall" || (b.type == "velocity" && normal == 0)) && p.turbulence.wall == "none")
      v.fail("turbulence.wall",
             fmt::format("face {} is a {}, and the standard k-epsilon model needs a wall "
                         "treatment there: use wall: two-layer (with the first cells at y+ of "
                         "about 1) or log-law (the first cell centres at y+ of 30 to 100)",
                         face_names()[f], b.type == "wall" ? "wall" : "moving wall"));
    if (f % 2 == 0 ? normal < 0 : normal > 0)
      v.fail("boundaries." + face_names()[f],
             fmt::format("the velocity face {} lets fluid out, and with fluid.turbulence a velocity face is an inlet "
                         "(k and epsilon enter there): use an outflow or pressure face where the fluid leaves",
                         face_names()[f]));
    const auto [key, what] = inlet_turbulence_key(b);
    if (b.type == "velocity" && normal == 0 && key)
      v.fail("boundaries." + face_names()[f] + "." + key,
             fmt::format("face {} lets no fluid through (its velocity has no {} component): {} are "
                         "for inlets; remove them here",
                         face_names()[f], "xyz"[f / 2], what));
    if (normal != 0 && !p.turbulence.inlet_given && !key)
      v.fail("turbulence",
             fmt::format("face {} is a velocity face: give the k and epsilon of what enters there, "
                         "on the face (boundaries.{}: {{..., k: ..., epsilon: ...}}, {{..., intensity: ..., "
                         "mixing_length: ...}} or {{..., turbulence_file: ...}}) or for every inlet "
                         "(turbulence.inlet: {{k: ..., epsilon: ...}})",
                         face_names()[f], face_names()[f]));
  }
}

// Criteria that could never mark a leaf in this run: bodies without immersed
// bodies, particles without point particles, walls in a box without walls, a
// box that misses the domain.
static void check_refinement_criteria(config::Visitor& v, const config::Config& cfg) {
  const std::string key = "fluid.fv.refinement.criteria";
  const auto& d = cfg.domain;
  const int dims = d.cells[2] == 1 ? 2 : 3;
  for (const auto& c : config::resolved_node(cfg, key)) {
    if (!c.IsMap()) continue;
    if (c["bodies"] && !(cfg.has("immersed") && cfg.component("immersed").variant == "ibm"))
      v.fail(key,
             "the criterion bodies refines around immersed bodies, and this run has none (immersed.method "
             "ibm): remove it, or refine by another criterion");
    if (c["particles"] && !config::point_coupling(cfg))
      v.fail(key,
             "the criterion particles refines where point particles put their momentum (immersed.method "
             "point), and this run has none: remove it, or refine by another criterion");
    const YAML::Node coupling = config::resolved_node(cfg, "particles.coupling");
    if (c["particles"] && coupling && coupling.IsScalar() && coupling.as<std::string>() == "one-way")
      v.fail(
          key,
          "the criterion particles refines where point particles put their momentum, and with "
          "particles.coupling: one-way they put none (no leaf would refine): remove it and refine by a box "
          "or another criterion, or couple two-way");
    bool walls = false;
    for (int a = 0; a < dims; ++a) walls = walls || !d.periodic[a];
    if (c["walls"] && !walls)
      v.fail(key,
             "the criterion walls refines near the box's non-periodic faces, and every axis is periodic: "
             "remove it, or refine by another criterion");
    const YAML::Node box = c["box"];
    if (!box || !box["lower"].IsSequence() || !box["upper"].IsSequence() || box["lower"].size() != 3 ||
        box["upper"].size() != 3)
      continue;
    bool meets = true;
    for (int a = 0; a < dims; ++a) {
      const double lo = box["lower"][a].as<double>(), hi = box["upper"][a].as<double>();
      meets = meets && std::isfinite(lo) && std::isfinite(hi) && hi > d.lower[a] && lo < d.upper[a];
    }
    if (!meets)
      v.fail(key,
             "the criterion box does not meet the domain (or a bound is not a finite number): no leaf would "
             "refine by it; give a box inside domain.lower .. domain.upper");
  }
}

// Immersed bodies on the adaptive grid: refined around by the `bodies`
// criterion, fixed, forced after the predictor.
static void check_refinement_bodies(config::Visitor& v, const config::Config& cfg) {
  const std::string key = "fluid.fv.refinement";
  bool bodies = false;
  for (const auto& c : config::resolved_node(cfg, "fluid.fv.refinement.criteria"))
    bodies = bodies || (c.IsMap() && c["bodies"]);
  if (!bodies)
    v.fail(key + ".criteria",
           "immersed.method ibm forces the fluid on the finest level: add `- bodies: {}` to the "
           "criteria, so that the leaves around the bodies refine to it");
  // The leaves refine around the markers where they are set; a moving body would leave them.
  const YAML::Node all = config::resolved_node(cfg, "immersed.ibm.bodies");
  for (std::size_t i = 0; all.IsSequence() && i < all.size(); ++i) {
    const YAML::Node& body = all;
    const YAML::Node m = body[i]["motion"];
    bool moves = false;
    for (const char* k : {"velocity", "angular_velocity", "amplitude", "angular_amplitude"}) {
      const YAML::Node& motion = m;
      if (motion.IsMap() && motion[k].IsSequence())
        for (const auto& x : motion[k]) moves = moves || x.as<double>() != 0.0;
    }
    if (moves)
      v.fail(
          fmt::format("immersed.ibm.bodies[{}].motion", i),
          "moving bodies do not run on fv's adaptive grid yet (its leaves refine where the markers are set): "
          "remove fluid.fv.refinement, or the motion");
  }
  if (config::resolved_text(cfg, {"immersed", "ibm", "stage"}) == "in_predictor")
    v.fail("immersed.ibm.stage",
           "the adaptive grid forces after its predictor only: use stage: after_predictor, or remove "
           "fluid.fv.refinement");
}

// What fv's adaptive grid does not take yet (fluid/fv/amr, issue 25): the
// uniform oracle, ramps, a pressure face other than the reference
// pressure 0; immersed boundaries need the `bodies` criterion.
static void check_refinement(config::Visitor& v, const config::Config& cfg, const std::string& variant) {
  if (!refined(cfg)) return;
  const std::string key = "fluid.fv.refinement";
  if (variant != "fv") {
    v.fail(key, fmt::format("solver {} is the uniform-grid oracle and does not refine; use solver: fv", variant));
    return;
  }
  check_refinement_criteria(v, cfg);
  FluidParams p;
  config::Reader r(config::resolved_node(cfg, "fluid"), cfg.file, "fluid");
  p.visit(r, cfg);
  if (turbulent(cfg) && config::resolved_text(cfg, {"fluid", "fv", "refinement", "diffusion"}) != "implicit")
    v.fail(key + ".diffusion",
           "k-epsilon on the adaptive grid needs `diffusion: implicit` (the eddy viscosity "
           "nu_t, often 100 nu and more, would hold an explicit step to h^2 / (4 d nu_t))");
  if (!turbulent(cfg))
    for (const auto& c : config::resolved_node(cfg, "fluid.fv.refinement.criteria"))
      if (c.IsMap() && c["k"])
        v.fail(key + ".criteria",
               "the criterion k needs the turbulence model: add fluid.turbulence (k-epsilon) "
               "or refine by another criterion");
  bool open = false;
  std::string profiled;  // a velocity face with flow through it and a profile
  for (int f = 0; f < 6; ++f) {
    const int a = f / 2;
    if (cfg.domain.periodic[a] || cfg.domain.cells[a] == 1) continue;
    const BoundaryParams b = p.boundary(f, cfg);
    const std::string at = "fluid.boundaries." + face_names()[f];
    open = open || b.type == "pressure" || b.type == "outflow";
    if (b.type == "velocity" && b.profile != "uniform" &&
        b.value.values.size() > static_cast<std::size_t>(a) &&
        b.value.values[static_cast<std::size_t>(a)] != 0.0 && profiled.empty())
      profiled = at;
    if (b.ramp > 0)
      v.fail(at + ".ramp",
             "the adaptive grid's faces take their value from the start: remove ramp, or refinement");
    if (b.formula.uses_time())
      v.fail(at + ".profile_expression",
             "the adaptive grid's faces hold their values in time: give a formula "
             "without t, or remove refinement");
    if (b.type == "pressure" && !b.value.values.empty() && b.value.values[0] != 0.0)
      v.fail(at + ".value", fmt::format("the adaptive grid's pressure faces hold the reference pressure 0 (got {} "
                                        "Pa): drive the flow by an inlet or fluid.body_force",
                                        b.value.values[0]));
  }
  // A closed box must let out what it lets in to round-off; the adaptive grid
  // takes a profile once per leaf face (at its centre), so a profiled face's
  // flux depends on the levels along it and would not balance.
  if (!open && !profiled.empty())
    v.fail(profiled + ".profile",
           "in a box with no pressure or outflow face the inflow must balance the outflow exactly, and the "
           "adaptive grid takes a profile once per leaf face, so the flux through it depends on the levels "
           "along it (but for a linear profile): give a uniform profile, add a pressure or outflow face, or "
           "remove refinement");
  if (cfg.has("immersed") && cfg.component("immersed").variant == "ibm") check_refinement_bodies(v, cfg);
}

// lbm's step dt = (tau - 1/2) dx^2 / (3 nu) must be a usable number: positive,
// finite and not subnormal (a viscosity of 1e308 made it 0, and a run
// "finished" with NaN momentum in series/fluid.csv), and few enough to count.
// (A step longer than the run is a warning of the report: report_lbm.)
static bool check_lbm_step(config::Visitor& v, const config::Config& cfg, const std::string& variant) {
  if (variant.rfind("lbm", 0) != 0) return true;
  const double nu = config::resolved_node(cfg, "fluid.viscosity").as<double>();
  const auto lp = config::read_section<lbm::LbmParams>(cfg, "fluid.lbm", "fluid.lbm");
  const double dx = cfg.domain.spacing()[0], dt = lbm::Units::from(dx, nu, 1.0, lp.tau).dt;
  const std::string step = fmt::format(
      "the lattice step dt = (tau - 1/2) dx^2 / (3 nu) = {} s (fluid.lbm.tau {}, dx {} m, fluid.viscosity {} "
      "m^2/s)",
      config::number(dt), config::number(lp.tau), config::number(dx), config::number(nu));
  const double end = cfg.run.end_time;
  if (!std::isnormal(dt) || dt < 0) {  // 0, subnormal, infinite or NaN
    v.fail("fluid.viscosity", step +
                                  " is not a usable positive number: give the viscosity in m^2/s of a real "
                                  "fluid (water 1e-6), and tau between 0.5 and about 2");
    return false;
  }
  if (end / dt > coupler::kMostWindows) {
    v.fail("run.end_time",
           fmt::format("{} s is {:.3g} steps of {}, more than the {:.0e} a run can count: shorten "
                       "run.end_time or lengthen the step",
                       config::number(end), end / dt, step, coupler::kMostWindows));
    return false;
  }
  return true;
}

// lbm steps by a fixed dt (from fluid.lbm.tau): a window the user gives must
// hold a whole number of them (the fluid would refuse it at its start).
// An automatic window is lbm's step (the only natural step offered), shortened
// to make run.output.every a whole number of windows where that costs at most
// 10 % (coupler::output_window): an output interval shorter than that window
// would skip snapshots or series rows, as run_config's check refuses for a
// given window.
// An external component may offer a step shorter than lbm's, which the
// window then takes (and lbm with it, at a smaller tau): the checks that take
// lbm's step for the window do not apply.
static bool external_in_run(const config::Config& cfg) {
  for (const char* c : {"fluid", "immersed", "particles"})
    if (cfg.has(c) && cfg.component(c).variant == "external") return true;
  return false;
}

static void check_lbm_auto_window(config::Visitor& v, const config::Config& cfg, const std::string& variant) {
  if (variant.rfind("lbm", 0) != 0 || !cfg.coupling.window.is_auto || external_in_run(cfg)) return;
  const double nu = config::resolved_node(cfg, "fluid.viscosity").as<double>(), dx = cfg.domain.spacing()[0];
  const auto lp = config::read_section<lbm::LbmParams>(cfg, "fluid.lbm", "fluid.lbm");
  const double w = coupler::output_window(lbm::Units::from(dx, nu, 1.0, lp.tau).dt, cfg);
  const auto& o = cfg.run.output;
  const std::pair<const char*, double> intervals[] = {
      {"run.output.every", o.every}, {"run.output.series_every", o.series_every.is_auto ? 0.0 : o.series_every.value}};
  for (const auto& [key, e] : intervals)
    if (e > 0 && e < w * (1 - 1e-9)) {
      v.fail(key, fmt::format("{} s is shorter than the coupling window, lbm's step dt = {} s (fluid.lbm.tau {} at "
                              "this grid and viscosity): a window writes one snapshot and one series row at most, "
                              "so some would be skipped; make it {} s or longer, or shorten the step "
                              "(fluid.lbm.tau {} gives dt = {} s)",
                              config::number(e), config::number(w), config::number(lp.tau), config::number(w),
                              config::number(0.5 + 3.0 * nu * e / (dx * dx)), config::number(e)));
      return;
    }
}

static void check_lbm_window(config::Visitor& v, const config::Config& cfg, const std::string& variant) {
  check_lbm_auto_window(v, cfg, variant);
  if (variant.rfind("lbm", 0) != 0 || cfg.coupling.window.is_auto) return;
  const double nu = config::resolved_node(cfg, "fluid.viscosity").as<double>();
  const auto lp = config::read_section<lbm::LbmParams>(cfg, "fluid.lbm", "fluid.lbm");
  const double dt = lbm::Units::from(cfg.domain.spacing()[0], nu, 1.0, lp.tau).dt;  // dt needs no density
  const double window = cfg.coupling.window.value, ratio = window / dt;
  if (whole_steps(window, dt) > 0) return;
  const double k = std::max(1.0, std::round(ratio));
  v.fail("coupling.window",
         fmt::format("{} s is {} lattice steps of dt = {} s (fluid.lbm.tau {} at this grid and "
                     "viscosity); give a whole number of them, e.g. {} s, or window: auto",
                     config::number(window), config::number(ratio), config::number(dt),
                     config::number(lp.tau), config::number(k * dt)));
}

// Two fluids on lbm: the blue fluid's relaxation time, 0.5 + 3 nu_blue dt /
// dx^2 as the fluid computes it, must exceed 1/2 as fluid.lbm.tau must (at
// 1/2 the harmonic mean of the two viscosities divides by zero).
static void check_lbm_blue_tau(config::Visitor& v, const config::Config& cfg, const std::string& variant) {
  if (variant.rfind("lbm", 0) != 0 || !config::resolved_node(cfg, "fluid.two_phase").IsMap()) return;
  const double nu = config::resolved_node(cfg, "fluid.viscosity").as<double>();
  const YAML::Node b = config::resolved_node(cfg, "fluid.two_phase.viscosity_blue");
  const double nu_b = b && b.as<double>() > 0.0 ? b.as<double>() : nu;
  const auto lp = config::read_section<lbm::LbmParams>(cfg, "fluid.lbm", "fluid.lbm");
  const double dx = cfg.domain.spacing()[0], dt = lbm::Units::from(dx, nu, 1.0, lp.tau).dt;
  const double tau_b = 0.5 + 3.0 * nu_b * dt / (dx * dx);
  if (tau_b > 0.5) return;
  v.fail("fluid.two_phase.viscosity_blue",
         fmt::format("{} m^2/s gives the blue fluid a relaxation time of {} (1/2 + (fluid.lbm.tau - 1/2) "
                     "viscosity_blue / viscosity); it must exceed 1/2: raise viscosity_blue or fluid.lbm.tau",
                     config::number(nu_b), config::number(tau_b)));
}

// The lattice Boltzmann fluids' immersed-boundary forcing reads and forces fluid cells only: its
// stencils must not reach into interior solids, so the two do not run together.
static void check_lbm_solids(config::Visitor& v, const config::Config& cfg, const std::string& variant) {
  if ((variant != "lbm" && variant != "lbm-reference") ||
      !config::resolved_node(cfg, "fluid.solids").IsSequence())
    return;
  if (!cfg.has("immersed") || cfg.component("immersed").variant != "ibm") return;
  v.fail("fluid.solids",
         "interior solids and immersed bodies (immersed.method ibm) do not run together on lbm or "
         "lbm-reference (the forcing's cells would reach into the solids): make the solid an immersed body, "
         "or the body "
         "an interior solid (fluid.solids takes STL meshes)");
}

// The wall functions (turbulence.wall: log-law) act at the box's walls of
// the uniform grid alone.
static void check_wall_functions(config::Visitor& v, const config::Config& cfg) {
  if (config::resolved_text(cfg, {"fluid", "turbulence", "wall"}) != "log-law") return;
  if (refined(cfg))
    v.fail("fluid.turbulence.wall", "the adaptive grid (fluid.fv.refinement) has no wall functions: use wall: "
                                    "two-layer there, or remove fluid.fv.refinement");
  if (cfg.has("immersed") && cfg.component("immersed").variant == "ibm")
    v.fail("fluid.turbulence.wall", "the wall functions (log-law) act at the box's walls only, and immersed.method "
                                    "ibm makes the bodies walls too: use wall: two-layer (its wall distance counts "
                                    "the bodies)");
}

// A pressure face whose lattice density 1 + p / (rho c_s^2) is not positive
// (at the step the run takes, with the window's shortening) has no meaning
// in the standard formulation: its closure divides by it.
// lbm's units at the step the coupling window asks for (coupler::output_window:
// tau adjusted), as the solver takes them.
static lbm::Units lbm_units(const config::Config& cfg, const FluidParams& p, const lbm::LbmParams& lp) {
  const double dx = cfg.domain.spacing()[0];
  const double natural = lbm::Units::from(dx, p.viscosity, p.density, lp.tau).dt;
  const double window = coupler::output_window(natural, cfg);
  const double tau = cfg.coupling.window.is_auto && window < natural * (1 - 1e-12)
                         ? lbm::tau_for_step(lp.tau, window, dx, p.viscosity)
                         : lp.tau;
  return lbm::Units::from(dx, p.viscosity, p.density, tau);
}

// A velocity face sets its cells' velocity: where that is above Mach 0.3
// within the run (its ramp counted; a formula in t with a ramp is left to
// the run), lbm stops at that step (LbmSolver's Mach check), so the
// configuration cannot run. Between 0.1 and 0.3 the report warns.
static void check_lbm_face_mach(config::Visitor& v, const config::Config& cfg, const std::string& variant) {
  if (variant.rfind("lbm", 0) != 0 || (cfg.coupling.window.is_auto && external_in_run(cfg))) return;
  const auto lp = config::read_section<lbm::LbmParams>(cfg, "fluid.lbm", "fluid.lbm");
  FluidParams p;
  config::Reader r(cfg.resolved["fluid"], cfg.file, "fluid");
  p.visit(r, cfg);
  const lbm::Units units = lbm_units(cfg, p, lp);
  for (int f = 0; f < 6; ++f) {
    const BoundaryParams b = p.boundary(f, cfg);
    if (b.type != "velocity" || (b.ramp > 0 && b.formula.uses_time())) continue;
    double speed = 0.0;
    for (double x : b.value.values) speed += x * x;
    speed = std::sqrt(speed) * largest_profile_factor(f, b, cfg) *
            (b.ramp > 0 ? std::min(1.0, cfg.run.end_time / b.ramp) : 1.0);
    const double mach = speed / units.velocity() * std::sqrt(3.0);
    if (!(mach > 0.3)) continue;
    // With dx and nu fixed, Mach is proportional to tau - 1/2 and to dx (report_mach).
    const double tau01 = 0.5 + (units.tau - 0.5) * 0.1 / mach, dx = cfg.domain.spacing()[0];
    v.fail(
        "fluid.boundaries." + face_names()[f] + ".value",
        fmt::format(
            "the face reaches {} m/s, Mach {} on this lattice (U dt/dx sqrt(3), dt = {} s): lbm stops "
            "above Mach 0.3, where the method is invalid; {}, or lower the velocity",
            config::number(speed), config::number(mach), config::number(units.dt),
            tau01 >= 0.51 ? fmt::format("fluid.lbm.tau {} gives Mach 0.1 at this dx", config::number(tau01))
                          : fmt::format("cells of {} m give Mach 0.1 at this tau (tau below 0.51 is "
                                        "unstable)",
                                        config::number(dx * 0.1 / mach))));
  }
}

static void check_lbm_pressure_faces(config::Visitor& v, const config::Config& cfg,
                                     const std::string& variant) {
  if (variant.rfind("lbm", 0) != 0) return;
  const auto lp = config::read_section<lbm::LbmParams>(cfg, "fluid.lbm", "fluid.lbm");
  if (lp.formulation != "standard") return;  // He-Luo's density is a pressure: any offset holds
  FluidParams p;
  config::Reader r(cfg.resolved["fluid"], cfg.file, "fluid");
  p.visit(r, cfg);
  const lbm::Units units = lbm_units(cfg, p, lp);
  for (const auto& [face, b] : p.boundaries) {
    if (b.type != "pressure" || b.value.values.empty() || units.lattice_density(b.value.values[0]) > 0.0)
      continue;
    v.fail("fluid.boundaries." + face + ".value",
           fmt::format(
               "{} Pa gives the face a lattice density of {} (1 + p / (rho c_s^2), with rho c_s^2 = {} Pa "
               "at this step): the standard formulation needs it positive, and within about 0.1 of 1; give "
               "pressures relative to "
               "a reference (the gauge pressure), or a shorter step (a smaller fluid.lbm.tau)",
               config::number(b.value.values[0]), config::number(units.lattice_density(b.value.values[0])),
               config::number(units.pressure() / 3.0)));
  }
}

// fv writes k, epsilon, nu_t and y_plus only where the turbulence model
// computes them: a laminar run wrote zeros.
static void check_turbulence_fields(config::Visitor& v, const config::Config& cfg, const std::string& variant) {
  if ((variant != "fv" && variant != "fv-reference") || turbulent(cfg)) return;
  for (const std::string& f : cfg.run.output.fields)
    if (f == "k" || f == "epsilon" || f == "nu_t" || f == "y_plus") {
      v.fail("run.output.fields", fmt::format("'{}' is the turbulence model's, and this fv fluid is laminar (no "
                                              "fluid.turbulence): add fluid.turbulence, or drop '{}'",
                                              f, f));
      return;
    }
}

static void check(config::Visitor& v, const config::Config& cfg, const std::string& variant) {
  check_wall_functions(v, cfg);
  check_turbulence_fields(v, cfg, variant);
  check_refinement(v, cfg, variant);
  if (!check_lbm_step(v, cfg, variant)) return;  // the checks below divide by dt
  check_lbm_window(v, cfg, variant);
  check_lbm_blue_tau(v, cfg, variant);
  check_lbm_solids(v, cfg, variant);
  check_lbm_planar(v, cfg, variant);
  check_lbm_pressure_faces(v, cfg, variant);
  check_lbm_face_mach(v, cfg, variant);
}

// The analytic fluid's flow is its field's (fluid.analytic) and
// fluid.initial.pressure: boundaries, a body force or an initial flow would be
// ignored, so they are refused.
static void check_analytic_keys(config::Visitor& v, const FluidParams& p) {
  const std::string why =
      "the analytic fluid prescribes its flow by fluid.analytic.field (and "
      "fluid.initial.pressure)";
  if (!p.boundaries.empty())
    v.fail("boundaries",
           why + ", which no boundary changes: remove fluid.boundaries, or take solver lbm or fv");
  if (p.body_force != Vec3{0, 0, 0})
    v.fail("body_force",
           why + ", which no body force drives: remove fluid.body_force, or take solver lbm or fv");
  if (p.initial_velocity != Vec3{0, 0, 0} || p.initial_field != "uniform" || p.initial_amplitude != 0.0)
    v.fail("initial", why +
                          ": give the flow as fluid.analytic (field uniform with velocity, taylor-green "
                          "with max_velocity, ...) and keep only initial.pressure");
}

config::ComponentSchema schema() {
  config::ComponentSchema s = component_schema("fluid", "solver", variant_schemas(),
                                                "the fluid component (omit the section, or solver: none, for no fluid)");
  s.writes = writes;
  s.contract = contract;
  s.report = report;
  s.resolve = resolve;
  s.check = check;
  s.visit = [s](config::Visitor& v, const config::Config& cfg, config::ComponentInfo& info) {
    config::visit_component_common(v, s, info);
    if (v.reading() && !has_variant(variant_schemas(), info.variant)) {  // external, none, or a wrong name reported above
      v.accept_other_keys();  // checked by the external executable itself
      return;
    }
    FluidParams p;
    p.visit(v, cfg);
    if (v.reading() && info.variant.rfind("fv", 0) != 0)
      for (const auto& [face, b] : p.boundaries)
        if (b.type == "symmetry")
          v.fail("boundaries." + face,
                 fmt::format("solver {} has no symmetry faces (fv has); use a wall, or a "
                             "periodic axis, or solver: fv",
                             info.variant));
    if (v.reading() && info.variant.rfind("lbm", 0) != 0) {
      if (p.two_phase.on) v.fail("two_phase", fmt::format("solver {} has one fluid; two_phase needs solver: lbm", info.variant));
      if (!p.solids.empty()) v.fail("solids", fmt::format("solver {} takes no interior solids; use solver: lbm", info.variant));
    }
    if (v.reading() && info.variant == "analytic") check_analytic_keys(v, p);
    check_open_face_blocks(v, cfg, info, p);
    check_fv_blocks(v, cfg, info);
    check_closed_box(v, cfg, info, p);
    check_turbulence(v, cfg, info, p);
    visit_variant_sections(v, cfg, info);
  };
  return s;
}

ComponentEntry schema_entry() { return {schema(), variant_schemas()}; }

}  // namespace coflow::fluid
