// Coupling contracts: what each variant provides to the other components of a
// run, what it needs from them, and which coupling schemes it runs. Every
// component's schema declares its variants' contracts; `coflow validate`
// matches them (check_contracts) so that an impossible combination is a
// configuration error with file:line:col, not an exception at run time or a
// silently wrong answer.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace coflow::config {

struct Config;
class Reader;

// The coupling scheme, chosen once from coupling.scheme (docs/protocol.md):
// serial-explicit: each window, the particle states go out and their loads come
//   back before the particles step;
// parallel-explicit: the particles step on the previous window's loads while
//   the fluid computes this window's.
enum class Scheme { serial_explicit, parallel_explicit };
const char* scheme_name(Scheme s);
Scheme scheme_from_name(const std::string& name);  // throws std::invalid_argument
const std::vector<std::string>& scheme_names();

// Where an exchanged quantity lives.
enum class Location { cell, point };

// An exchanged quantity: name, where it lives, SI units.
struct Field {
  std::string name;
  Location location = Location::cell;
  std::string units;
};

// The fields the components exchange (docs/config.md, "Coupling contracts"). A contract names
// them by these constants, so that provider and consumer spell them alike.
namespace fields {
inline const Field velocity{"velocity", Location::cell, "m/s"};
inline const Field pressure{"pressure", Location::cell, "Pa"};
inline const Field k{"k", Location::cell, "m^2/s^2"};
inline const Field epsilon{"epsilon", Location::cell, "m^2/s^3"};
inline const Field solid_fraction{"solid_fraction", Location::cell, "1"};
inline const Field solid_force{"solid_force", Location::cell, "N"};
inline const Field momentum_source{"momentum_source", Location::cell, "N/m^3"};
inline const Field particle_state{"particle_state", Location::point, "m, m/s, rad/s"};
inline const Field hydrodynamic_load{"hydrodynamic_load", Location::point, "N, N m"};
inline const Field fluid_at_particle{"fluid_at_particle", Location::point, "m/s, 1/s, m^2/s^2, m^2/s^3, kg/m^3, Pa s"};
inline const Field impulse{"impulse", Location::point, "N s"};
// cos(contact angle) of the grains in partially saturated cells: a two-phase
// fluid takes it.
inline const Field grain_wetting{"grain_wetting", Location::cell, "1"};
// Immersed-boundary markers (immersed.method ibm): a fluid that takes them
// iterates the multi-direct forcing in its own steps and returns the bodies' loads.
inline const Field ibm_forcing{"ibm_forcing", Location::point, "m, m/s, m^3; N, N m"};
}  // namespace fields

// A field a variant needs. `key` is the configuration key that makes it need
// the field (where validate points); `only_with` names a component section
// whose absence voids the need (a component running alone needs no partner).
struct Need {
  Need(Field f, std::string k, std::string with = "", std::string other = "")
      : field(std::move(f)), key(std::move(k)), only_with(std::move(with)), otherwise(std::move(other)) {}
  Field field;
  std::string key;
  std::string only_with;
  std::string otherwise;  // another fix, e.g. "or dispersion.model: none"
};

struct Contract {
  bool open = false;  // an external variant: its contract is its own business
  std::vector<Field> provides;
  std::vector<Need> needs;
  std::vector<Scheme> schemes{Scheme::serial_explicit, Scheme::parallel_explicit};

  bool provides_field(const std::string& name) const;
  bool runs(Scheme s) const;
};

// Match the contracts of the run's components; each failure goes to `r` at the
// key responsible, with the variants that would fix it.
struct ComponentSchema;
void check_contracts(Reader& r, const Config& cfg, const std::vector<ComponentSchema>& catalog);

}  // namespace coflow::config
