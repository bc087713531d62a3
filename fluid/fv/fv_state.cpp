// fv: what the solver shows and keeps: snapshot fields, diagnostics, the
// momentum source it takes, checkpoint and restart.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <utility>

#include "coflow/output.hpp"
#include "fluid/fv/fv_solver.hpp"
#include "fluid/grid/cell_fields.hpp"

namespace coflow::fluid {

std::vector<output::GridField> FvSolver::fields(const config::StringList& names) {
  const std::size_t N = static_cast<std::size_t>(blk_.owned_cells());
  out_u_.assign(3 * N, 0.0);
  out_p_ = owned_of(p_field_);
  out_rho_.assign(N, rho_);
  out_div_.assign(N, 0.0);
  for_owned([&](const long*, long n, long o) {
    const auto O = static_cast<std::size_t>(o);
    for (int c = 0; c < dims_; ++c) {
      const auto& q = u_[static_cast<std::size_t>(c)];
      out_u_[3 * O + static_cast<std::size_t>(c)] = 0.5 * (q[n] + q[n + stride(c)]);  // the cell's centre
    }
    out_div_[O] = divergence_at(u_, n);
  });
  // The turbulence fields (zero for laminar flow), kept until the next call.
  const std::vector<double> none(N, 0.0);
  out_k_ = turbulent_ ? owned_of(k_) : none;
  out_eps_ = turbulent_ ? owned_of(eps_) : none;
  out_nut_ = turbulent_ ? owned_of(nut_) : none;
  out_yplus_ = y_plus();
  return named_fields(names, {out_u_, out_p_, out_rho_, out_div_, out_k_, out_eps_, out_nut_, out_yplus_});
}

// The snapshot fields by name from their arrays over the owned cells (also
// fv-reference's).
std::vector<output::GridField> FvSolver::named_fields(const config::StringList& names, const Arrays& a) {
  std::vector<output::GridField> f;
  for (const auto& n : names) {
    if (n == "velocity") f.push_back({n, 3, a.u});
    if (n == "pressure") f.push_back({n, 1, a.p});
    if (n == "density") f.push_back({n, 1, a.rho});
    if (n == "divergence") f.push_back({n, 1, a.div});
    if (n == "k") f.push_back({n, 1, a.k});
    if (n == "epsilon") f.push_back({n, 1, a.eps});
    if (n == "nu_t") f.push_back({n, 1, a.nut});
    if (n == "y_plus") f.push_back({n, 1, a.y_plus});
  }
  return f;
}

// Mass, momentum and kinetic energy of this rank's cells from their centre
// velocities (3 per cell), cells of mass m; fv-reference's too.
Diagnostics FvSolver::cell_diagnostics(const std::vector<double>& u, double m) {
  Diagnostics d;
  for (std::size_t o = 0; 3 * o < u.size(); ++o) {
    double u2 = 0.0;
    for (std::size_t c = 0; c < 3; ++c) {
      d.momentum[c] += m * u[3 * o + c];
      u2 += u[3 * o + c] * u[3 * o + c];
    }
    d.mass += m;
    d.kinetic_energy += 0.5 * m * u2;
    d.max_velocity = std::max(d.max_velocity, std::sqrt(u2));
  }
  return d;
}

// A rank's sums and largest velocity to the component's.
void FvSolver::reduce(Diagnostics& d, MPI_Comm comm) {
  double sums[5] = {d.mass, d.momentum[0], d.momentum[1], d.momentum[2], d.kinetic_energy};
  MPI_Allreduce(MPI_IN_PLACE, sums, 5, MPI_DOUBLE, MPI_SUM, comm);
  MPI_Allreduce(MPI_IN_PLACE, &d.max_velocity, 1, MPI_DOUBLE, MPI_MAX, comm);
  d.mass = sums[0];
  d.momentum = {sums[1], sums[2], sums[3]};
  d.kinetic_energy = sums[4];
}

Diagnostics FvSolver::diagnostics() {
  fields({});
  Diagnostics d = cell_diagnostics(out_u_, rho_ * h_[0] * h_[1] * h_[2]);
  reduce(d, comm_);
  d.extra = {static_cast<double>(window_steps_), last_dt_, static_cast<double>(poisson_iterations_),
             static_cast<double>(viscous_iterations_), max_divergence_};
  if (turbulent_) add_turbulence_diagnostics(d);
  return d;
}

// The means of k and epsilon over the cells, the largest nu_t and the largest
// y+ of the cells next to walls, the largest iterations of the k and epsilon
// solves in the window.
void FvSolver::add_turbulence_diagnostics(Diagnostics& d) {
  double sums[2] = {0, 0}, most[2] = {0, 0};
  const auto yp = y_plus();
  for_owned([&](const long*, long n, long o) {
    sums[0] += k_[n];
    sums[1] += eps_[n];
    most[0] = std::max(most[0], nut_[n]);
    most[1] = std::max(most[1], yp[static_cast<std::size_t>(o)]);
  });
  MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_DOUBLE, MPI_SUM, comm_);
  MPI_Allreduce(MPI_IN_PLACE, most, 2, MPI_DOUBLE, MPI_MAX, comm_);
  const double cells = static_cast<double>(cells_[0] * cells_[1] * cells_[2]);
  d.extra.insert(d.extra.end(), {sums[0] / cells, sums[1] / cells, most[0], most[1],
                                 static_cast<double>(turbulence_iterations_)});
  turbulence_iterations_ = 0;
}

std::vector<output::Series::Column> FvSolver::series_columns() const { return columns(turbulent_); }

// Also fv-reference's (which does not count its iterations: zero there).
std::vector<output::Series::Column> FvSolver::columns(bool turbulent) {
  std::vector<output::Series::Column> c{{"steps", "1"},
                                        {"dt", "s"},
                                        {"poisson_iterations", "1"},
                                        {"viscous_iterations", "1"},
                                        {"max_divergence", "1/s"}};
  if (turbulent) {
    const auto t = turbulence_columns("turbulence_iterations");
    c.insert(c.end(), t.begin(), t.end());
  }
  return c;
}

std::vector<output::Series::Column> FvSolver::turbulence_columns(const std::string& effort) {
  return {{"k_mean", "m^2/s^2"},
          {"epsilon_mean", "m^2/s^3"},
          {"nu_t_max", "m^2/s"},
          {"y_plus_max", "1"},
          {effort, "1"}};
}

// The point particles' momentum source at the cells (N/m^3), taken at the
// faces as the mean of the two cells beside (seed 003 eq. 3.43).
void FvSolver::set_source(std::span<const double> force_density) {
  for (int c = 0; c < dims_; ++c) {
    auto& s = source_[static_cast<std::size_t>(c)];
    for_owned(
        [&](const long*, long n, long o) { s[n] = force_density[3 * static_cast<std::size_t>(o) + c]; });
    ex_.exchange(s);
  }
  have_source_ = source_fresh_ = true;
}

namespace {

std::vector<double> interleave(const std::array<std::vector<double>, 3>& parts) {
  std::vector<double> v(3 * parts[0].size());
  for (std::size_t o = 0; o < parts[0].size(); ++o)
    for (std::size_t c = 0; c < 3; ++c) v[3 * o + c] = parts[c][o];
  return v;
}

}  // namespace

// The state: face velocities of this step and the last, the upper open
// faces, the last advection term, the last step's momentum source (at the
// cells), the pressure and its last two increments (the Poisson solve's first
// guess); the clock (steps, time, the last two steps) as exact hexadecimal
// numbers.
void FvSolver::save(const std::string& dir) {
  auto faces = [&](const Faces& f) { return interleave({owned_of(f[0]), owned_of(f[1]), owned_of(f[2])}); };
  const auto u = faces(u_), top = faces(top_), old = faces(u_old_), adv = faces(adv_old_),
             p = owned_of(p_field_), phi = owned_of(phi_), phi_old = owned_of(phi_old_), src = faces(source_old_);
  grid::save_cell_fields(comm_, dir + "/fv.h5", time_, steps_, cells_, blk_.owned,
                         {{"velocity_faces", 3, u},
                          {"velocity_upper", 3, top},
                          {"velocity_previous", 3, old},
                          {"advection_previous", 3, adv},
                          {"pressure", 1, p},
                          {"pressure_increment", 1, phi},
                          {"pressure_increment_previous", 1, phi_old},
                          {"source_previous", 3, src}});
  if (turbulent_)
    grid::save_cell_fields(comm_, dir + "/fv_turbulence.h5", time_, steps_, cells_, blk_.owned,
                           {{"k", 1, owned_of(k_)},
                            {"epsilon", 1, owned_of(eps_)},
                            {"k_change", 1, owned_of(k_change_)},  // first guesses
                            {"epsilon_change", 1, owned_of(eps_change_)}});
  // The most iterations of a k or epsilon solve since the last series row: a
  // checkpoint between two rows (windows shorter than series_every) keeps it.
  if (turbulent_)
    grid::save_number(comm_, dir + "/fv_turbulence_iterations.txt",
                      static_cast<double>(turbulence_iterations_));
  grid::save_text(comm_, dir + "/fv_clock.txt",
                  fmt::format("{} {:a} {:a} {:a}\n", steps_, time_, dt_prev_, dt_prev2_));
}

void FvSolver::load(const std::string& dir, long, double) {
  const std::string path = dir + "/fv.h5";
  auto faces = [&](const std::string& name, Faces& f) {
    const auto v = grid::load_cell_field(path, name, cells_, blk_.owned, 3);
    for (std::size_t c = 0; c < 3; ++c)
      for_owned([&](const long*, long n, long o) { f[c][n] = v[3 * static_cast<std::size_t>(o) + c]; });
  };
  faces("velocity_faces", u_);
  faces("velocity_upper", top_);
  faces("velocity_previous", u_old_);
  faces("advection_previous", adv_old_);
  faces("source_previous", source_old_);
  for (auto& f : source_old_) ex_.exchange(f);
  set_owned(p_field_, grid::load_cell_field(path, "pressure", cells_, blk_.owned, 1));
  set_owned(phi_, grid::load_cell_field(path, "pressure_increment", cells_, blk_.owned, 1));  // first guesses
  set_owned(phi_old_, grid::load_cell_field(path, "pressure_increment_previous", cells_, blk_.owned, 1));
  std::ifstream clock(dir + "/fv_clock.txt");
  std::string t, dt, dt2;
  if (!(clock >> steps_ >> t >> dt >> dt2))
    throw std::runtime_error(
        fmt::format("fv: {}/fv_clock.txt is missing or unreadable: restart from a checkpoint "
                    "written by the fv solver (since 4a74140 the clock holds the last two steps)",
                    dir));
  time_ = std::strtod(t.c_str(), nullptr);
  dt_prev_ = std::strtod(dt.c_str(), nullptr);
  dt_prev2_ = std::strtod(dt2.c_str(), nullptr);
  viscous_key_ = {0, 0, 0};
  fill_ghosts(u_, time_);
  fill_pressure_ghosts(p_field_, time_, false, time_);
  if (turbulent_) {
    const std::string tpath = dir + "/fv_turbulence.h5";
    set_owned(k_, grid::load_cell_field(tpath, "k", cells_, blk_.owned, 1));
    set_owned(eps_, grid::load_cell_field(tpath, "epsilon", cells_, blk_.owned, 1));
    // The solves' first guesses; a checkpoint from before they were kept has
    // none, and the solves then start from k and epsilon themselves.
    for (auto [name, field] : {std::pair{"k_change", &k_change_}, std::pair{"epsilon_change", &eps_change_}}) {
      if (output::has_dataset(tpath, name))
        set_owned(*field, grid::load_cell_field(tpath, name, cells_, blk_.owned, 1));
      else
        std::fill(field->begin(), field->end(), 0.0);
    }
    turbulence_iterations_ = static_cast<int>(
        grid::load_number(dir + "/fv_turbulence_iterations.txt", 0.0));  // 0: an older checkpoint
    set_inlet_lines(time_);
    fill_scalar_ghosts(k_, inlet_k_, log_law_ ? 1.0 : 0.0, true);
    fill_scalar_ghosts(eps_, inlet_eps_, 1.0, true);
    update_eddy_viscosity();
    check_positive(time_,
                   fmt::format("{} holds them: the checkpoint is damaged; restart from another one", tpath),
                   false);
  }
}

}  // namespace coflow::fluid
