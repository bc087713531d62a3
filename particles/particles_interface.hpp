// The particle component's interface. Variants register in particles/variants.cpp.
#pragma once

#include <mpi.h>

#include <array>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "coflow/config.hpp"
#include "coflow/decomposition.hpp"
#include "coflow/reproducible_sum.hpp"
#include "coflow/run_config.hpp"

namespace coflow::particles {

using config::Vec3;

struct SpeciesParams {
  double density = 2650.0;
  config::Distribution diameter{config::Distribution::Kind::fixed, 1e-3, 0.0};
  bool fixed = false;  // held in place (obstacles, a sphere array): forces act on it but it does not move
  double contact_angle = -1.0;  // two-phase psm: degrees, in the red fluid; -1: fluid.two_phase.contact_angle
  void visit(config::Visitor& v);
};

struct BondParams {
  double compressive_strength = 0.0;  // Pa
  double tensile_strength = 0.0;      // Pa
  double shear_strength = 0.0;        // Pa
  double crush_fraction = 0.01;
  double gap = 0.0;                   // m: pairs closer than this at start are bonded
  config::FilePath pairs;             // optional CSV of bonded id pairs (then only those)
  void visit(config::Visitor& v);
};

struct ContactParams {
  double normal_stiffness = 1e4;  // N/m
  double shear_stiffness = 1e4;   // N/m
  double friction = 0.5;
  double local_damping = 0.0;     // alpha of seed 000 eqs 2.9-2.10
  bool bonded = false;            // a `bond` section was given
  BondParams bond;
  void visit(config::Visitor& v);
};

struct WallParams {
  std::string face;         // x-, ..., z+
  config::FilePath mesh;    // STL file (triangle-mesh wall)
  double restitution = 1.0;
  double friction = -1.0;  // < 0: the contact friction
  double scale = 1.0;      // mesh: factor on the file's coordinates
  Vec3 translate{0, 0, 0}; // mesh: shift in m after the scale
  void visit(config::Visitor& v);
};

// Hard-sphere collisions of point particles (dpm): pairs, and the default for
// walls.
struct CollisionPairParams {
  config::StringList species;  // two species names
  double restitution = 1.0;
  double friction = 0.0;
  void visit(config::Visitor& v);
};
struct CollisionParams {
  double restitution = 1.0;
  double friction = 0.0;
  bool enabled = true;
  std::vector<CollisionPairParams> pairs;  // per species pair, overriding the above
  void visit(config::Visitor& v);
};

// Turbulent dispersion of point particles (dpm): Langevin model, seed 003 eqs
// 3.35-3.42.
struct DispersionParams {
  std::string model = "none";  // none | langevin
  double C_T = 0.22;           // eq. 3.38
  // msd: the mean-square lateral displacement after each particle crosses a
  // plane (seed 003 eq. 5.24) into series/dispersion.csv (dpm).
  bool msd = false;
  int msd_axis = 0;
  double msd_plane = 0.0, msd_interval = 0.0;
  int msd_samples = 0;
  void visit(config::Visitor& v);
};

// One item of `initial`.
struct InitialItem {
  std::string kind;  // single | lattice | random | file
  std::string species;
  Vec3 position{0, 0, 0};
  Vec3 velocity{0, 0, 0};
  Vec3 angular_velocity{0, 0, 0};
  double spacing = 0.0;
  Vec3 lower{0, 0, 0}, upper{0, 0, 0};
  int count = 0;
  double volume_fraction = 0.0;
  double velocity_std = 0.0;
  config::FilePath path;
};

// One inlet of point particles (dpm): a mass flow through a disk or a
// rectangle (seed 003 §4.2.2.4, eqs 4.18-4.19; spread as eq. 5.20 in 3D).
struct InjectionParams {
  std::string species;
  double mass_flow = 0.0;  // kg/s
  double speed = 0.0;      // m/s
  Vec3 direction{0, 0, 0}; // of the jet; zero: the face's normal
  double spread_angle = 0.0;  // degrees, half-angle of the cone of directions
  double start = 0.0, stop = -1.0;  // s; stop < 0: never
  bool disk = true;
  Vec3 center{0, 0, 0}, normal{0, 0, 1}, axis{0, 0, 0};
  double diameter = 0.0;   // disk
  Vec3 size{0, 0, 0};      // rectangle: lengths along axis and normal x axis (third entry unused)
  void visit(config::Visitor& v);
};

// Keys common to the particle variants (see docs/config.md).
struct ParticleParams {
  config::AutoDouble time_step;
  double time_step_fraction = 0.1;
  std::vector<std::pair<std::string, SpeciesParams>> species;
  ContactParams contact;
  CollisionParams collision;
  DispersionParams dispersion;
  config::StringList forces{"gravity_buoyancy", "drag", "saffman_lift", "magnus_lift", "torque"};
  std::vector<WallParams> walls;
  std::array<std::string, 6> boundaries{"", "", "", "", "", ""};  // per face; "" = default
  std::vector<InitialItem> initial;
  std::vector<InjectionParams> injection;  // dpm
  std::string coupling = "two-way";        // dpm with point: two-way | one-way
  void visit(config::Visitor& v, const config::Config& cfg);
  void visit_boundaries(config::Visitor& v, const config::Config& cfg);
  void check_wall_faces(config::Visitor& v, const config::Config& cfg) const;
  void visit_initial(config::Visitor& v);
  void check_references(config::Visitor& v) const;
  void check_initial_overlaps(config::Visitor& v) const;
  void check_random_fills(config::Visitor& v) const;
  void check_files(config::Visitor& v) const;
  void check_time_step(config::Visitor& v) const;
  // Placement against the domain and the blocks of `info`'s decomposition:
  // particles larger than the domain or than a block, and particles, regions,
  // inlets and meshes outside the domain (validate time).
  void check_geometry(config::Visitor& v, const config::Config& cfg, const config::ComponentInfo& info) const;
  void check_meshes_inside(config::Visitor& v, const config::Config& cfg) const;
  void check_file_inside(config::Visitor& v, const config::Config& cfg,
                         std::size_t n) const;  // initial item n
  int species_index(const std::string& name) const;
  // Where a message about initial item n (its `field`; "" the item) points:
  // initial[n].<kind>.<field>.
  std::string initial_key(std::size_t n, const std::string& field) const;
  // "unknown species 'x'" with the closest defined name, and how to fix it.
  std::string unknown_species(const std::string& name) const;
  bool point_particles = false;  // a dpm variant (set from particles.solver)
};

// The largest diameter a particle of these species can have (log-normal: mean
// + 6 standard deviations), m.
double largest_diameter(const ParticleParams& p);
// What is wrong with the datasets' lengths of a particle snapshot (n radii:
// 3n positions, velocities and angular velocities, n species), or "".
std::string snapshot_shape_error(std::size_t radii, std::size_t positions, std::size_t velocities,
                                 std::size_t angular_velocities, std::size_t species);
// The automatic particle step from the species alone (validate time), over
// the species the initial items other than files place (none: those the
// inlets bring, `arriving`). largest: each at its largest diameter, an upper
// bound of the step the run starts with (no grain it starts with has a
// longer one: the refusal of check_step_count); otherwise at its smallest, a
// lower bound (the report's wall time; a log-normal species has none). dem's
// step is contact.hpp's automatic_step (equal to the run's for one size);
// dpm's 0.2 of the response time with the fluid section's density and
// viscosity (seed 003 eq. 4.15; velocities, collisions and dispersion only
// shorten it). step 0: no estimate (dpm without drag or fluid, no such
// species).
struct StepEstimate {
  double step = 0.0;      // s
  std::string species;    // the species that sets it
  bool arriving = false;  // the species come through the inlets, not at the start
};
StepEstimate automatic_step_estimate(const ParticleParams& p, const config::Config& cfg, bool largest);
// The particles section read as a variant reads it (after resolution).
ParticleParams read_particle_params(const config::Config& cfg, const std::string& variant);
// particles.time_step, given or auto, against the number of steps a run can
// count (the schema's cross-section check).
void check_step_count(config::Visitor& v, const config::Config& cfg, const std::string& variant);
// Width, in fluid cells, of the ghost layer through which particle states reach
// the immersed ranks: every cell a particle covers is then reached.
int coupling_ghost_cells(const ParticleParams& p, const config::Config& cfg);

// Particle states, structure of arrays (3 entries per particle for vectors).
struct ParticleArrays {
  std::vector<std::int64_t> id;
  std::vector<std::int32_t> species;
  std::vector<double> x, v, w;  // position, velocity, angular velocity
  std::vector<double> radius, mass, inertia;
  std::vector<double> force;   // last contact + wall force, for output
  std::size_t size() const { return id.size(); }
};

// Global statistics, reduced over the component.
struct ParticleStats {
  long count = 0;
  Vec3 momentum{0, 0, 0};
  double kinetic_energy = 0.0;     // translational
  double rotational_energy = 0.0;
  long collisions = 0;          // contacts formed since the previous call
  long wall_collisions = 0;
  long broken_bonds = 0;        // since the start (cumulative)
};

// Discrete events, for events/collisions.csv and events/bonds.csv.
struct CollisionEvent {
  double time = 0.0;
  std::int64_t i = 0, j = 0;   // particle ids, i < j
  double angle = 0.0;          // between the relative velocity and the line of centres, degrees
  double relative_speed = 0.0, normal_speed = 0.0;  // m/s, at first touch
};
enum class BondFailure { tension = 1, compression = 2, shear = 3 };
struct BondEvent {
  double time = 0.0;
  std::int64_t i = 0, j = 0;
  BondFailure mode = BondFailure::tension;
  double normal_force = 0.0;   // N, > 0 compressive, at failure
  double shear_force = 0.0;    // N, magnitude at failure
};
// A particle hitting a wall (a domain face or a triangle of a mesh).
struct ImpactEvent {
  double time = 0.0;
  std::int64_t id = 0;
  std::int64_t wall = 0;        // face 0-5 (x-, x+, ...), or 6 + (mesh << 24) + triangle
  Vec3 point{0, 0, 0};          // contact point, m
  double angle = 0.0;           // between the velocity and the wall's plane, degrees (90: head-on)
  double speed = 0.0;           // m/s, before the impact
};
struct ParticleEvents {
  std::vector<CollisionEvent> collisions;
  std::vector<ImpactEvent> impacts;
  std::vector<BondEvent> bonds;
};

// A particle that left through an outlet: its window's fluid impulse, and
// where it was last inside (ParticleSolver::take_departed).
struct DepartedImpulse {
  std::int64_t id = 0;
  std::array<double, 3> x{};
  std::array<double, 3> impulse{};
};

class ParticleSolver {
 public:
  struct Setup {
    const config::Config& cfg;
    const ParticleParams& params;
    coupler::Decomposition decomposition;
    int rank = 0;
    MPI_Comm comm = MPI_COMM_NULL;
  };
  virtual ~ParticleSolver() = default;

  virtual double time_step() const = 0;  // natural step, s
  // Advance by dt in `substeps` equal steps; hydrodynamic loads held constant.
  virtual void advance(double dt, long substeps) = 0;
  virtual double time() const = 0;
  virtual long steps() const = 0;
  virtual const ParticleArrays& particles() const = 0;  // this rank's
  // Hydrodynamic force and torque per local particle (3 per particle), held
  // constant until the next call.
  virtual void set_hydrodynamic(std::span<const double> force, std::span<const double> torque) = 0;
  // Point particles (immersed method point): the fluid at each local particle,
  // kFluidValues per particle (u[3], vorticity[3], k, epsilon, rho, mu; SI),
  // held until the next call; and the impulse of the fluid forces on each
  // local particle since the last call (N s, 3 per particle), for the momentum
  // source of seed 003 eq. 3.43. Particle solvers without them throw.
  // The samples follow the local particles' order, then that of
  // probe_points(): points where the solver wants the fluid without a
  // particle there (the inlets' faces, for particles that enter within the
  // window).
  static constexpr int kFluidValues = 10;
  virtual std::vector<std::array<double, 3>> probe_points() const { return {}; }
  virtual void set_fluid(std::span<const double> samples) {
    (void)samples;
    throw std::runtime_error("this particle solver takes forces, not the fluid at the particles (use psm)");
  }
  virtual void take_impulse(std::vector<double>& impulse) { impulse.clear(); }
  // The particles that left through an outlet in the last advance() (not yet
  // taken), each with the impulse of the fluid forces on it over the window
  // until it left (N s) and its position at the start of the step it left
  // in: the fluid takes that impulse back there (point coupling; two-way
  // momentum with outlets).
  virtual void take_departed(std::vector<DepartedImpulse>& departed) { departed.clear(); }
  virtual ParticleStats stats() = 0;  // collective; resets the event counters
  // The impulse (N s) this rank's particles gave each wall since the last
  // call (wall_impulse.hpp: 3 per wall, the six faces then the mesh walls),
  // kept exactly so that 1 rank and N give the same series/walls.csv.
  virtual coupler::ExactSums take_wall_impulse() = 0;
  // Record discrete events (off by default); take_events() hands over and clears
  // this rank's record.
  virtual void record_events(bool collisions, bool bonds) {
    (void)collisions;
    (void)bonds;
  }
  virtual ParticleEvents take_events() { return {}; }

  // Checkpoint and restart (collective): particles and contact histories.
  virtual void save(const std::string& dir) = 0;
  virtual void load(const std::string& dir, long steps, double time) = 0;
  // Statistics files of the variant's own into `series_dir` (collective; at
  // every series row). dpm: dispersion.csv (particles.dispersion.msd).
  virtual void write_statistics(const std::string& series_dir) { (void)series_dir; }
};

}  // namespace coflow::particles
