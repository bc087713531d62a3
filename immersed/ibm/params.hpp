// immersed.ibm: bodies as triangle meshes for the multi-direct-forcing
// immersed boundary (seed 003 §4.2.1), and how the fluid iterates it.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "coflow/config.hpp"
#include "coflow/run_config.hpp"
#include "coflow/stl.hpp"
#include "immersed/ibm/direct_forcing.hpp"

namespace coflow::immersed {

using config::Vec3;

// A body's prescribed motion: its reference point c(t) = centre + velocity t +
// amplitude sin(2 pi frequency t) and a rotation at angular_velocity about it.
struct BodyMotion {
  config::Numbers centre;  // [x, y, z] m, or empty: the mesh's centroid
  Vec3 velocity{0, 0, 0};
  Vec3 angular_velocity{0, 0, 0};
  Vec3 amplitude{0, 0, 0};
  Vec3 angular_amplitude{0, 0, 0};  // rad, about its direction (parallel to angular_velocity)
  double frequency = 0.0;
  bool moves() const;
  bool turns() const;
};

struct BodyParams {
  std::string name;
  config::FilePath mesh;
  double scale = 1.0;
  Vec3 translate{0, 0, 0};
  BodyMotion motion;
  void visit(config::Visitor& v);
};

struct IbmParams {
  std::string kernel = "hat";
  double spacing = 1.0;     // cells between markers
  double retraction = 0.0;  // cells: markers moved into the body along the normal
  std::string iteration = "cg";
  std::string stage = "after_predictor";  // fv: where the forcing acts on the momentum step
  int max_iterations = 50;
  double tolerance = 1e-4;
  std::string particles = "none";  // none | point: point particles coupled in the same windows
  std::vector<BodyParams> bodies;
  void visit(config::Visitor& v);
  void check(config::Visitor& v, const config::Config& cfg) const;
  ibm::ForcingParams forcing() const {
    return {ibm::kernel_from_name(kernel), max_iterations, tolerance, iteration == "cg"};
  }
};

// The mesh of a body, scaled and moved as its keys say.
stl::TriangleMesh load_body_mesh(const BodyParams& b);
// The fluid grid as the markers see it.
ibm::GridGeometry grid_geometry(const config::DomainParams& d);
// immersed.ibm of a resolved configuration (the fluid reads it too).
IbmParams read_ibm_params(const config::Config& cfg);
// A fluid's forcing on its staggered grid (fv, fv-reference), as immersed.ibm says.
std::unique_ptr<ibm::DirectForcing> staggered_forcing(const config::Config& cfg, std::array<bool, 3> periodic,
                                                      std::function<long(int, const std::array<long, 3>&)> index,
                                                      MPI_Comm comm);
// A fluid's forcing on its cell centres (lbm, lbm-reference): the domain's
// periodic axes, velocities in units of velocity_unit m/s.
std::unique_ptr<ibm::DirectForcing> collocated_forcing(const config::Config& cfg,
                                                       std::function<long(const std::array<long, 3>&)> index,
                                                       double velocity_unit, MPI_Comm comm);

}  // namespace coflow::immersed
