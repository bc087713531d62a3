// The k-epsilon model with the two-layer wall treatment (seed 003 eqs.
// 3.13-3.25) on the composite grid of fv's adaptive refinement: k, epsilon
// and nu_t are forest components (carried by regrids and checkpoints with
// the velocity), stepped after each step of the flow (composite_flow.hpp)
// with its new velocity:
//
//   1. advection, explicit, in sub-steps of Courant number at most 1, by
//      the projection's face velocities, the face values limited upwind
//      (van Leer, as on the uniform grid: fv::face_value) from the four
//      values along each face's axis, the same number from either side, in
//      non-divergent form;
//   2. diffusion (nu + nu_t / sigma) implicit, by two-point fluxes between
//      the cells either side of each composite face (centres h apart on one
//      level, 3/2 of the fine spacing across levels), nu_t the two cells'
//      mean, with the sources as on the uniform grid (closure.hpp): the
//      production P = nu_t S^2 explicit, the destruction linearised about
//      the old values and implicit (Patankar 1980). A flux through a
//      coarse-fine face is the same number seen from either side: k and
//      epsilon move between levels without loss. One sparse system per
//      quantity and step (GMRES + BoomerAMG, as the projection's);
//   3. in the one-equation layer (Re_y < Re_y*) epsilon from eq. 3.18 (held
//      in epsilon's system as a fixed value); nu_t from eqs. 3.17,
//      3.21-3.25.
//
// Positivity by construction: the limited face values lie between 0 and
// twice their upwind cell's value, so each advection sub-step (sum of
// |flux| dt / V at most 1) keeps a cell at least (1 - that sum) times its
// old value; the implicit matrix is an M-matrix (positive diagonal above
// the sum of its non-positive couplings) and its right-hand side
// non-negative, so the solution is positive (to the solver's tolerance);
// refining a leaf caps the transfer's slopes (ForestSpec::positive_from).
// The run stops (never clips) if a value is not positive: that would be a
// bug.
//
// Why two-point diffusive fluxes, not the composite Laplacian's: across
// levels its coarse-fine fluxes (Martin & Cartwright) interpolate with
// weights of both signs, and would not keep k positive; the two-point flux
// does, at first order where the grid changes level. The limited face value
// falls to first order where the cell one further upstream is on a coarser
// level than the face's cells, or beyond a wall or an outlet.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "fluid/fv/amr/composite_flow.hpp"
#include "fluid/turbulence_params.hpp"

namespace coflow::fluid::fv::amr {

class CompositeTurbulence {
 public:
  // k, epsilon and nu_t in the forest's components first .. first + 2;
  // `lower`, `upper`: the domain's corners (for the walls' distance).
  // `solve`: where the implicit systems stop.
  CompositeTurbulence(CompositeFlow& flow, Forest& forest, const TurbulenceParams& params, double nu,
                      int first, const std::array<double, 3>& lower, const std::array<double, 3>& upper,
                      IjSystem::Options solve);
  // k and epsilon entering through a domain face (x-, x+, y-, ...) beside
  // the point x (a cell's centre); by default params.inlet's everywhere.
  using Inlets = std::function<std::array<double, 2>(int face, const std::array<double, 3>& x)>;
  void set_inlets(Inlets inlets) {
    inlet_ = std::move(inlets);
    find_upstream();  // it keeps the values beyond the inlets
  }

  // The initial k and epsilon on every leaf cell (epsilon of eq. 3.18 in
  // the one-equation layer), and nu_t.
  void set_initial();
  // After a regrid (the flow's operators rebuilt): the walls' distance of
  // the new cells, and nu_t from the carried k and epsilon.
  void after_regrid();
  // A distance to immersed bodies, taken with the box's walls (seed 003
  // §3.1.2: y to the nearest wall); nu_t again.
  void set_body_distance(std::function<double(const std::array<double, 3>&)> distance);
  // After a restart from `file`: k and epsilon positive, C_mu k^2 /
  // epsilon finite and the stored nu_t finite and not negative in every
  // cell, or every rank throws, naming the file (a damaged checkpoint).
  // Collective.
  void check_loaded(const std::string& file) const;
  // One step of length dt with the flow's new velocity (see the top).
  void step(double dt);
  // Advection and diffusion alone (no sources): what the conservation test checks.
  void transport(double dt);
  // The largest nu_t per level; the smallest nu_t anywhere (collective both).
  std::vector<double> largest_eddy_viscosity() const;
  double smallest_eddy_viscosity() const;
  // y+ = y u_tau / nu at the centres of cells beside a wall (zero elsewhere),
  // u_tau from the cell's Gauss gradient of the tangential velocity (collective).
  std::vector<double> y_plus();
  // sum V k, sum V epsilon and sum V over all ranks.
  std::array<double, 3> totals() const;
  int last_substeps() const { return substeps_; }
  int last_iterations() const { return iterations_; }  // the most of the last step's two solves

 private:
  struct Link;
  // The value one cell further upstream than a face's near cells, for the
  // limited upwind face value: none (first order there), a stencil of slots
  // (a leaf cell or the mean of finer ones), or beyond an inlet the line
  // through the inlet's value and the cell (never below 0).
  struct Upstream {
    enum Kind { none, stencil, inlet };
    Kind self_kind = none, across_kind = none;
    std::array<double, 2> self_inlet{}, across_inlet{};  // inlet: k and epsilon entering there
    std::array<double, 2> own_inlet{};  // a domain face's sub-face at an inlet: k and epsilon entering
    Stencil self, across;  // beyond this cell, beyond the cell across
  };
  std::vector<std::vector<Link>> links(const std::vector<double>& nut) const;
  void find_upstream();
  double face_value(const std::vector<double>& q, int quantity, std::size_t c, const Link& l) const;
  std::vector<std::vector<Link>> current_links() const;  // the forest's ghosts exchanged before
  void advect(const std::vector<std::vector<Link>>& all, double dt);
  void diffuse(const std::vector<std::vector<Link>>& all, int q, double dt, const std::vector<double>& sink,
               const std::vector<double>& source, const std::vector<char>* fixed);
  double& at(std::size_t cell, int q) const;  // the forest's component first + q of local cell `cell`
  void update_distance();
  void update_eddy_viscosity();
  void check_positive() const;

  CompositeFlow& flow_;
  Forest& forest_;
  TurbulenceParams params_;
  Inlets inlet_;  // k and epsilon entering through the domain faces
  double nu_;
  int first_;
  std::array<double, 3> lower_, upper_;
  std::function<double(const std::array<double, 3>&)> body_;
  std::vector<double> y_;  // per local cell, the distance to the nearest wall (infinite: none)
  std::vector<std::vector<Upstream>> upstream_;  // per local cell and sub-face
  IjSystem::Options solve_;
  int substeps_ = 0, iterations_ = 0;
};

}  // namespace coflow::fluid::fv::amr
