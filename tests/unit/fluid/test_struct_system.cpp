// StructSystem's conjugate gradients preconditioned by the diagonal (its own
// loops, hypre's ghost exchange) on a viscous-type system with face
// coefficients that vary from face to face, as fv's momentum and k-epsilon
// solves with an eddy viscosity: the residual recomputed here from the whole
// matrix is within the tolerance, the solution agrees with the same matrix
// solved by hypre's PCG + PFMG (the other path of the same class), and with
// periodic axes the images are coupled. Runs on any rank count (`unit` 1
// rank, `unit.mpi_4_ranks` 4).
#include <mpi.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <vector>

#include "coflow/decomposition.hpp"
#include "fluid/fv/struct_system.hpp"

using coflow::coupler::Decomposition;
using coflow::coupler::Index3;
using coflow::fluid::fv::StructSystem;

namespace {

// The coefficient of the face above global cell g along d (a smooth but
// irregular field, the same on every rank).
double face_coefficient(const long* g, int d) {
  return 1.0 + 0.8 * std::sin(1.3 * static_cast<double>(g[0]) + 0.7 * static_cast<double>(g[1]) +
                              2.1 * static_cast<double>(g[2]) + static_cast<double>(d));
}

struct Global {
  Index3 cells;
  std::array<bool, 3> periodic;
  int dims;
  long index(const long* g) const { return (g[2] * cells[1] + g[1]) * cells[0] + g[0]; }
  // The neighbour of g along d on `side` (0 below, 1 above), or false across a wall.
  bool neighbour(const long* g, int d, int side, long* nb) const {
    for (int a = 0; a < 3; ++a) nb[a] = g[a];
    nb[d] += side == 0 ? -1 : 1;
    if (nb[d] < 0 || nb[d] >= cells[static_cast<std::size_t>(d)]) {
      if (!periodic[static_cast<std::size_t>(d)]) return false;
      nb[d] = (nb[d] + cells[static_cast<std::size_t>(d)]) % cells[static_cast<std::size_t>(d)];
    }
    return true;
  }
  // Row g: its couplings below and above along each axis, and its diagonal.
  double row(const long* g, double mass, double* lo, double* hi) const {
    double diag = mass;
    for (int d = 0; d < dims; ++d)
      for (int side = 0; side < 2; ++side) {
        long nb[3];
        double& c = side == 0 ? lo[d] : hi[d];
        c = 0.0;
        if (!neighbour(g, d, side, nb)) continue;
        c = -face_coefficient(side == 0 ? nb : g, d);
        diag -= c;
      }
    return diag;
  }
};

struct Assembled {
  StructSystem::Rows m;
  std::vector<double> b;
  std::vector<long> global;  // each owned cell's global index
};

template <class F>
void for_box(const coflow::coupler::Box& box, F f) {
  std::size_t o = 0;
  for (long k = box.lo[2]; k < box.hi[2]; ++k)
    for (long j = box.lo[1]; j < box.hi[1]; ++j)
      for (long i = box.lo[0]; i < box.hi[0]; ++i, ++o) {
        const long g[3] = {i, j, k};
        f(g, o);
      }
}

Assembled assemble(const Global& G, const coflow::coupler::Box& box, double mass) {
  const auto n = static_cast<std::size_t>(box.volume());
  Assembled a{StructSystem::Rows(n), std::vector<double>(n), std::vector<long>(n)};
  for_box(box, [&](const long* g, std::size_t o) {
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    a.m.diag[o] = G.row(g, mass, lo, hi);
    for (std::size_t d = 0; d < 3; ++d) a.m.lower[d][o] = lo[d], a.m.upper[d][o] = hi[d];
    a.b[o] = std::cos(0.3 * static_cast<double>(g[0] * g[0]) + 0.5 * static_cast<double>(g[1]) -
                      0.2 * static_cast<double>(g[2]));
    a.global[o] = G.index(g);
  });
  return a;
}

// |b - A x| / |b|, A x from the whole solution gathered on every rank; row(g,
// o, lo, hi) gives cell g's (owned o) diagonal and couplings.
template <class Row>
double residual(const Global& G, const coflow::coupler::Box& box, const Assembled& a,
                const std::vector<double>& x, Row row) {
  const long total = G.cells[0] * G.cells[1] * G.cells[2];
  std::vector<double> all(static_cast<std::size_t>(total), 0.0);
  for (std::size_t c = 0; c < x.size(); ++c) all[static_cast<std::size_t>(a.global[c])] = x[c];
  MPI_Allreduce(MPI_IN_PLACE, all.data(), static_cast<int>(total), MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  double sums[2] = {0, 0};
  for_box(box, [&](const long* g, std::size_t o) {
    double lo[3], hi[3];
    double ax = row(g, o, lo, hi) * x[o];
    for (int d = 0; d < G.dims; ++d)
      for (int side = 0; side < 2; ++side) {
        long nb[3];
        if (G.neighbour(g, d, side, nb))
          ax += (side == 0 ? lo : hi)[d] * all[static_cast<std::size_t>(G.index(nb))];
      }
    sums[0] += (a.b[o] - ax) * (a.b[o] - ax), sums[1] += a.b[o] * a.b[o];
  });
  MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  return std::sqrt(sums[0] / sums[1]);
}

// The residual with the matrix recomputed from the global grid.
double true_residual(const Global& G, const coflow::coupler::Box& box, double mass, const Assembled& a,
                     const std::vector<double>& x) {
  return residual(G, box, a, x,
                  [&](const long* g, std::size_t, double* lo, double* hi) { return G.row(g, mass, lo, hi); });
}

// The residual with A the rows as handed to the solver (a.m).
double rows_residual(const Global& G, const coflow::coupler::Box& box, const Assembled& a,
                     const std::vector<double>& x) {
  return residual(G, box, a, x, [&](const long*, std::size_t o, double* lo, double* hi) {
    for (std::size_t d = 0; d < 3; ++d) lo[d] = a.m.lower[d][o], hi[d] = a.m.upper[d][o];
    return a.m.diag[o];
  });
}

coflow::coupler::Box my_box(const Global& G) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const Decomposition dec(G.cells, size, {0, 0, 0}, G.periodic);
  return dec.block(rank);
}

std::array<bool, 3> hypre_periodic(const Global& G) {
  std::array<bool, 3> per = G.periodic;
  if (G.dims == 2) per[2] = true;
  return per;
}

struct Outcome {
  double residual = 0.0, difference = 0.0;
  int iterations = 0;
};

Outcome solve_both(const Global& G, double mass) {
  const auto box = my_box(G);
  Assembled a = assemble(G, box, mass);
  std::vector<double> x(a.b.size(), 0.0), x_mg(a.b.size(), 0.0);
  StructSystem jacobi(MPI_COMM_WORLD, box, G.cells, hypre_periodic(G), {"pfmg", 1e-12, 500, "test"});
  StructSystem mg(MPI_COMM_WORLD, box, G.cells, hypre_periodic(G), {"pfmg", 1e-13, 200, "test"});
  jacobi.use_diagonal(true);
  StructSystem::Rows copy = a.m;
  jacobi.take(copy);
  mg.set(a.m);
  jacobi.solve(a.b, x);
  mg.solve(a.b, x_mg);
  double sums[2] = {0, 0};  // |x - x_mg|^2, |x_mg|^2
  for (std::size_t c = 0; c < x.size(); ++c)
    sums[0] += (x[c] - x_mg[c]) * (x[c] - x_mg[c]), sums[1] += x_mg[c] * x_mg[c];
  MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  return {true_residual(G, box, mass, a, x), std::sqrt(sums[0] / sums[1]), jacobi.last_iterations()};
}

}  // namespace

TEST_CASE("struct system: the diagonal PCG solves a varying-coefficient system", "[fv][mpi]") {
  const struct {
    Global g;
    double mass;
  } cases[] = {
      {{{24, 20, 1}, {false, false, false}, 2}, 4.0},  // walls all round
      {{{24, 20, 1}, {true, false, false}, 2}, 4.0},   // periodic along x
      {{{12, 10, 8}, {false, true, false}, 3}, 6.0},   // 3D, periodic along y
      {{{12, 10, 8}, {true, true, true}, 3}, 0.5},     // 3D, periodic all round, weakly dominant
  };
  for (const auto& c : cases) {
    const Outcome r = solve_both(c.g, c.mass);
    INFO("cells " << c.g.cells[0] << "x" << c.g.cells[1] << "x" << c.g.cells[2] << ", iterations "
                  << r.iterations << ", residual " << r.residual << ", against PFMG " << r.difference);
    CHECK(r.iterations > 1);
    CHECK(r.residual <= 1e-12);    // the stopping rule, recomputed from the whole matrix
    CHECK(r.difference <= 7.3e-12);  // against PCG + PFMG to 1e-13 (4.5e-13 to 7.3e-13 measured)
  }
}

// A second matrix in the same system (1 / a_ii again), then the multigrid path
// after matrices handed over in the diagonal one (hypre's copy made then).
// True residuals 2.9e-13 to 7.3e-13 measured (bound 2e-12, the solver's 1e-12
// plus the drift of the recursively updated residual).
TEST_CASE("struct system: a new matrix, and the multigrid after the diagonal", "[fv][mpi]") {
  const Global G{{20, 16, 1}, {true, false, false}, 2};
  const auto box = my_box(G);
  StructSystem sys(MPI_COMM_WORLD, box, G.cells, hypre_periodic(G), {"pfmg", 1e-12, 500, "test"});
  sys.use_diagonal(true);
  for (double mass : {4.0, 0.3}) {
    Assembled a = assemble(G, box, mass);
    std::vector<double> x(a.b.size(), 0.0);
    sys.take(a.m);
    sys.solve(a.b, x);
    const double res = true_residual(G, box, mass, a, x);
    INFO("mass " << mass << ", diagonal PCG, residual " << res);
    CHECK(res <= 2e-12);
  }
  Assembled a = assemble(G, box, 0.3);
  std::vector<double> x(a.b.size(), 0.0);
  sys.use_diagonal(false);
  sys.solve(a.b, x);
  const double res = true_residual(G, box, 0.3, a, x);
  INFO("PCG + PFMG after the diagonal path, residual " << res);
  CHECK(res <= 2e-12);
  std::vector<double> bad = a.b;
  bad[0] = std::numeric_limits<double>::quiet_NaN();
  sys.use_diagonal(true);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank != 0) bad = a.b;  // one rank's NaN reaches every rank through the sums
  CHECK_THROWS_WITH(sys.solve(bad, x), Catch::Contains("not finite"));
}

TEST_CASE("struct system: a right-hand side of zero gives x = 0", "[fv]") {
  const Global g{{8, 6, 1}, {false, false, false}, 2};
  const Decomposition dec(g.cells, 1, {0, 0, 0}, g.periodic);
  StructSystem s(MPI_COMM_SELF, dec.block(0), g.cells, {false, false, true}, {"pfmg", 1e-12, 50, "test"});
  s.use_diagonal(true);
  StructSystem::Rows m(48);
  for (auto& d : m.diag) d = 2.0;
  s.set(m);
  std::vector<double> b(48, 0.0), x(48, 3.0);
  s.solve(b, x);
  for (double v : x) CHECK(v == 0.0);
}

// The product reads a symmetric matrix's lower couplings from the upper ones
// (the same numbers; checked in the first product with each matrix); a
// matrix that is not symmetric, here one cell's lower couplings on every rank
// a tenth larger than their partners, takes the general product. Each solves to the tolerance with the
// residual recomputed from its own rows: both within the solve's tolerance,
// 1e-12, and the rounding of the recomputed residual, 2e-12 as the other
// residual checks in this file (measured 8.1e-13 to 9.3e-13 on 1, 2 and 4
// ranks); the skewed one would miss by about 1e-3 if its product read the
// partners.
TEST_CASE("struct system: a matrix symmetric to the bit and one that is not", "[fv][mpi]") {
  for (const Global G :
       {Global{{24, 20, 1}, {false, false, false}, 2}, Global{{12, 10, 8}, {true, false, false}, 3}}) {
    const auto box = my_box(G);
    Assembled a = assemble(G, box, 4.0), skew = assemble(G, box, 4.0);
    const long nx = box.hi[0] - box.lo[0], ny = box.hi[1] - box.lo[1];
    // A cell with its lower neighbours along every axis in the block.
    const auto o = static_cast<std::size_t>((G.dims == 3 ? nx * ny : 0) + nx + 2);
    for (std::size_t d = 0; d < static_cast<std::size_t>(G.dims); ++d) skew.m.lower[d][o] *= 1.1;
    StructSystem s(MPI_COMM_WORLD, box, G.cells, hypre_periodic(G), {"pfmg", 1e-12, 500, "test"});
    s.use_diagonal(true);
    std::vector<double> x(a.b.size(), 0.0), y(a.b.size(), 0.0);
    s.set(a.m);
    s.solve(a.b, x);
    s.set(skew.m);
    s.solve(skew.b, y);
    const double rs = rows_residual(G, box, a, x), rn = rows_residual(G, box, skew, y);
    INFO(G.dims << "D: residual " << rs << " (symmetric), " << rn << " (not symmetric)");
    CHECK(rs <= 2e-12);
    CHECK(rn <= 2e-12);
  }
}

// A matrix that is not positive definite (the varying-coefficient Laplacian
// shifted by -3 times the identity: eigenvalues of both signs). hypre's PCG
// stops early when <p, A p> or <r, M r> is not positive; such a stop short of
// the tolerance is an error (before 2026-12-05 it was accepted, and only
// running out of iterations threw). The positive definite system beside it
// still solves.
TEST_CASE("struct system: conjugate gradients that break down are an error", "[fv][mpi]") {
  const Global G{{32, 20, 1}, {true, false, false}, 2};
  const auto box = my_box(G);
  for (const char* mg : {"pfmg", "smg"}) {
    StructSystem s(MPI_COMM_WORLD, box, G.cells, hypre_periodic(G), {mg, 1e-12, 500, "test"});
    Assembled bad = assemble(G, box, -3.0), good = assemble(G, box, 4.0);
    std::vector<double> x(bad.b.size(), 0.0);
    s.set(bad.m);
    INFO(mg);
    CHECK_THROWS_WITH(s.solve(bad.b, x), Catch::Contains("broke down"));
    std::fill(x.begin(), x.end(), 0.0);
    s.set(good.m);
    s.solve(good.b, x);
    CHECK(true_residual(G, box, 4.0, good, x) <= 2e-12);
  }
}

// hypre's SMG breaks down when a periodic axis does not have a power of two
// cells (20, 24, 40, 48 measured to fail; 2, 16, 32, 64 converge): with 20
// its PCG stopped after one iteration and the solve was accepted with x far
// from the solution before 2026-12-05. Validation refuses such a grid
// (tests/config/bad/fv_smg_periodic_not_power_of_two.yaml); here the solver
// itself says so, and 32 cells solve.
TEST_CASE("struct system: SMG on a periodic axis of 20 cells is an error, of 32 a solution", "[fv][mpi]") {
  for (const long n : {20L, 32L}) {
    const Global G{{n, 16, 1}, {true, false, false}, 2};
    const auto box = my_box(G);
    StructSystem s(MPI_COMM_WORLD, box, G.cells, hypre_periodic(G), {"smg", 1e-12, 500, "test"});
    Assembled a = assemble(G, box, 4.0);
    std::vector<double> x(a.b.size(), 0.0);
    s.set(a.m);
    INFO(n << " cells");
    if (n == 20) {
      CHECK_THROWS_WITH(s.solve(a.b, x), Catch::Contains("broke down"));
    } else {
      s.solve(a.b, x);
      CHECK(true_residual(G, box, 4.0, a, x) <= 2e-12);
    }
  }
}
