// The immersed boundary's pieces: the kernels' moment conditions (Roma,
// Peskin & Berger 1999; Peskin 2002), the markers' sampling of a mesh (areas,
// normals, spacing), the closed mesh's volume, the marker message, and the
// multi-direct forcing on a grid: it drives the markers' velocity to the
// bodies' and conserves the force it spreads.
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <numbers>

#include "immersed/ibm/direct_forcing.hpp"
#include "immersed/ibm/kernels.hpp"
#include "immersed/ibm/markers.hpp"

using namespace coflow;
using ibm::Kernel;

namespace {

// A closed cube [0, a]^3 of 12 triangles, normals out.
stl::TriangleMesh cube(double a) {
  stl::TriangleMesh m;
  for (int k = 0; k < 8; ++k) m.vertices.push_back(stl::V3((k & 1) * a, ((k >> 1) & 1) * a, ((k >> 2) & 1) * a));
  m.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return m;
}

ibm::GridGeometry grid(double h, long n, int dims) {
  ibm::GridGeometry g;
  g.lower = {-0.5, -0.5, -0.5};
  g.cells = {n, n, dims == 2 ? 1 : n};
  g.h = {h, h, dims == 2 ? 0.1 : h};
  g.dims = dims;
  return g;
}

}  // namespace

TEST_CASE("each kernel is a partition of unity with its published second sums", "[immersed][ibm]") {
  // sum_i phi(r - i) = 1 and sum_i (r - i) phi(r - i) = 0 for any r; the
  // 3-point kernel has sum phi^2 = 1/2 (Roma, Peskin & Berger 1999, their 3-point
  // function), the 4-point one sum phi^2 = 3/8 (Peskin 2002): the conditions they were built from.
  for (Kernel k : {Kernel::hat, Kernel::roma3, Kernel::peskin4}) {
    for (double r = 0.0; r < 1.0; r += 0.0625) {
      double s0 = 0, s1 = 0, s2 = 0;
      for (int i = -3; i <= 3; ++i) {
        const double w = ibm::kernel(k, r - i);
        s0 += w, s1 += (r - i) * w, s2 += w * w;
      }
      CHECK(s0 == Approx(1.0).margin(1e-14));
      CHECK(s1 == Approx(0.0).margin(1e-14));
      if (k == Kernel::roma3) CHECK(s2 == Approx(0.5).margin(1e-14));
      if (k == Kernel::peskin4) CHECK(s2 == Approx(0.375).margin(1e-14));
    }
    CHECK(ibm::kernel(k, ibm::kernel_radius(k)) == 0.0);
  }
}

TEST_CASE("markers sample a mesh with its area, outward normals, about a cell apart", "[immersed][ibm]") {
  const double a = 0.4, h = 0.02;
  const auto g = grid(h, 50, 3);
  const auto pts = ibm::sample_surface(cube(a), g, 1.0);
  double area = 0;
  for (const auto& p : pts) {
    area += p.area;
    // on the surface, the normal out of the nearest face
    const double cx = p.x[0] - a / 2, cy = p.x[1] - a / 2, cz = p.x[2] - a / 2;
    const double dot = p.normal[0] * cx + p.normal[1] * cy + p.normal[2] * cz;
    CHECK(dot > 0);
  }
  CHECK(area == Approx(6 * a * a).epsilon(1e-12));
  // One marker per cell-sized box: about the surface over h^2 (a box on an
  // edge holds pieces of two faces).
  CHECK(pts.size() >= static_cast<std::size_t>(6 * (a / h - 1) * (a / h - 1)));
  CHECK(pts.size() <= static_cast<std::size_t>(6 * (a / h + 1) * (a / h + 1)));
  const ibm::MeshVolume v = ibm::mesh_volume(cube(a));
  CHECK(v.volume == Approx(a * a * a).epsilon(1e-12));
  CHECK(v.centroid[0] == Approx(a / 2).epsilon(1e-12));
  // Second moments about the origin, exact for a polyhedron: the integral of
  // x^2 over [0, a]^3 is a^5 / 3, of x y a^5 / 4.
  CHECK(v.second[0] == Approx(std::pow(a, 5) / 3).epsilon(1e-12));
  CHECK(v.second[4] == Approx(std::pow(a, 5) / 3).epsilon(1e-12));
  CHECK(v.second[1] == Approx(std::pow(a, 5) / 4).epsilon(1e-12));
  CHECK(v.second[5] == Approx(std::pow(a, 5) / 4).epsilon(1e-12));
  CHECK(v.second[6] == v.second[2]);
  // The inertia about a corner (the origin): a^5 (2/3, 2/3, 2/3) on the
  // diagonal, -a^5 / 4 off it; about any point p, the parallel axes from the
  // centroid's a^5 / 6: I_c + V (|r|^2 1 - r r^T), r = centroid - p.
  const auto corner = ibm::inertia_about(v, {0, 0, 0});
  CHECK(corner[0] == Approx(2 * std::pow(a, 5) / 3).epsilon(1e-12));
  CHECK(corner[1] == Approx(-std::pow(a, 5) / 4).epsilon(1e-12));
  const ibm::Vec p{0.3, -0.2, 0.7};
  const auto at_p = ibm::inertia_about(v, p);
  const double r[3] = {a / 2 - p[0], a / 2 - p[1], a / 2 - p[2]},
               r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const double expected = (i == j ? std::pow(a, 5) / 6 + v.volume * r2 : 0.0) - v.volume * r[i] * r[j];
      CHECK(at_p[static_cast<std::size_t>(3 * i + j)] == Approx(expected).epsilon(1e-12).margin(1e-15));
    }
}

TEST_CASE("a 2D fluid sees a prism by its outline: perimeter times the slab", "[immersed][ibm]") {
  const double a = 0.4;
  stl::TriangleMesh m = cube(a);  // a square prism of length a along z
  const auto g = grid(0.02, 50, 2);
  double area = 0;
  for (const auto& p : ibm::sample_surface(m, g, 1.0)) area += p.area;
  CHECK(area == Approx(4 * a * g.h[2]).epsilon(1e-12));  // the caps count nothing
}

TEST_CASE("the marker message round-trips", "[immersed][ibm]") {
  ibm::MarkerSet s;
  s.time = 1.25;
  s.bodies = {{{1, 2, 3}, {0.5, 0, 0}, {0, -2, 0}}};
  s.markers = {{{0.1, 0.2, 0.3}, {0.5, 0, 0}, 0.75, 0},
               {{0.4, 0.5, 0.6}, {0.5, 0.1, 0}, 1.5, 0, {0, 0, 4}, {0.6, 0, -0.8}}};
  const ibm::MarkerSet r = ibm::MarkerSet::unpack(s.pack());
  CHECK(r.time == 1.25);
  REQUIRE(r.markers.size() == 2);
  CHECK(r.markers[1].x[2] == 0.6);
  CHECK(r.markers[1].volume_ratio == 1.5);
  CHECK(r.markers[1].body == 0);
  CHECK(r.markers[1].a[2] == 4);
  CHECK(r.markers[1].n[0] == 0.6);
  CHECK(r.markers[1].n[2] == -0.8);
  CHECK(r.bodies[0].centre[1] == 2);
  CHECK(r.bodies[0].acceleration[1] == -2);
}

TEST_CASE("a marker moves at constant acceleration within a window", "[immersed][ibm]") {
  // x(s) = x + u s + a s^2 / 2 and u(s) = u + a s: exact for a uniformly
  // accelerated point (and for a translation, a = 0).
  const ibm::Marker m{{1, 2, 3}, {0.5, -1, 0}, 1.0, 0, {2, 0, -4}};
  const auto x = m.x_at(0.5), u = m.u_at(0.5);
  CHECK(x[0] == Approx(1 + 0.25 + 0.25).epsilon(1e-15));
  CHECK(x[1] == Approx(2 - 0.5).epsilon(1e-15));
  CHECK(x[2] == Approx(3 - 0.5).epsilon(1e-15));
  CHECK(u[0] == Approx(1.5).epsilon(1e-15));
  CHECK(u[2] == Approx(-2).epsilon(1e-15));
}

TEST_CASE("multi-direct forcing drives the markers to the body's velocity and conserves the force",
          "[immersed][ibm]") {
  // A ring of markers (a cylinder of radius 0.2 on a 2D collocated grid of
  // h = 0.02) started in a uniform stream u = 1: one direct forcing halves the
  // slip (I S's smooth modes have eigenvalues near sum phi^2 = 1/2), 20
  // repeats leave 4.2e-3 (the iteration is Richardson's, slow on the modes the
  // kernel smooths away), conjugate gradients reach 1e-6; the change of the
  // grid's momentum equals the force the markers report (the kernel sums to one).
  const long n = 50;
  const auto g = grid(0.02, n, 2);
  ibm::DirectForcing::Grid gr;
  gr.geometry = g;
  for (int c = 0; c < 2; ++c) {
    ibm::DirectForcing::Points p;
    p.index = [n](const std::array<long, 3>& x) { return x[0] < 0 || x[0] >= n || x[1] < 0 || x[1] >= n ? -1 : x[1] * n + x[0]; };
    gr.components.push_back(p);
  }
  ibm::DirectForcing f(gr, {Kernel::roma3, 20, 1e-6}, MPI_COMM_WORLD);
  ibm::MarkerSet s;
  s.bodies = {{{0, 0, 0}, {0, 0, 0}}};
  const int markers = 63;
  for (int m = 0; m < markers; ++m) {
    const double th = 2 * std::numbers::pi * m / markers, ds = 2 * std::numbers::pi * 0.2 / markers;
    s.markers.push_back({{0.2 * std::cos(th), 0.2 * std::sin(th), 0}, {0, 0, 0}, ds / 0.02, 0});
  }
  f.set_markers(s);
  std::vector<double> u(static_cast<std::size_t>(n * n), 1.0), v(static_cast<std::size_t>(n * n), 0.0);
  const double dt = 0.01, factor = 1.0 / dt;  // rho = 1, alpha2 = 1
  ibm::DirectForcing one(gr, {Kernel::roma3, 1, 1e-6}, MPI_COMM_WORLD);
  one.set_markers(s);
  std::vector<double> u1(u.size(), 1.0), v1(v.size(), 0.0);
  const double first = one.apply({u1.data(), v1.data(), nullptr}, 0.0, 1.0, factor, dt).slip;
  const auto r = f.apply({u.data(), v.data(), nullptr}, 0.0, 1.0, factor, dt);
  CHECK(first < 0.6);
  CHECK(r.slip < 1e-2);
  CHECK(r.iterations == 20);
  ibm::DirectForcing cg(gr, {Kernel::roma3, 200, 1e-6, true}, MPI_COMM_WORLD);
  cg.set_markers(s);
  std::vector<double> u2(u.size(), 1.0), v2(v.size(), 0.0);
  const auto rc = cg.apply({u2.data(), v2.data(), nullptr}, 0.0, 1.0, factor, dt);
  CHECK(rc.slip <= 1e-6);
  CHECK(rc.iterations < 100);
  WARN("conjugate gradients: " << rc.iterations << " iterations to a slip of " << rc.slip);
  double momentum = 0;
  for (double x : u) momentum += (x - 1.0) * g.cell_volume();
  const auto loads = f.take_loads();  // the body's: minus the fluid's
  CHECK(-loads[0] == Approx(momentum / dt).epsilon(1e-10));
  CHECK(loads[1] == Approx(0.0).margin(1e-10 * std::abs(loads[0])));
}

namespace {

// A 2D collocated n x n grid of h = 0.02 about the origin (both components
// stored alike) and a ring of 63 markers of radius 0.2 at rest.
ibm::DirectForcing::Grid ring_grid(long n) {
  ibm::DirectForcing::Grid gr;
  gr.geometry = grid(0.02, n, 2);
  for (int c = 0; c < 2; ++c) {
    ibm::DirectForcing::Points p;
    p.index = [n](const std::array<long, 3>& x) {
      return x[0] < 0 || x[0] >= n || x[1] < 0 || x[1] >= n ? -1 : x[1] * n + x[0];
    };
    gr.components.push_back(p);
  }
  return gr;
}

ibm::MarkerSet ring(int markers) {
  ibm::MarkerSet s;
  s.bodies = {{{0, 0, 0}, {0, 0, 0}}};
  for (int m = 0; m < markers; ++m) {
    const double th = 2 * std::numbers::pi * m / markers, ds = 2 * std::numbers::pi * 0.2 / markers;
    s.markers.push_back({{0.2 * std::cos(th), 0.2 * std::sin(th), 0}, {0, 0, 0}, ds / 0.02, 0});
  }
  return s;
}

}  // namespace

TEST_CASE("with a varying density the bodies take exactly the opposite of the fluid's force",
          "[immersed][ibm]") {
  // lbm's standard formulation: a point takes the force factor rho_x dU_x;
  // the loads take the density interpolated at each marker, so that the sum
  // over the grid of factor rho_x dU_x dV and the bodies' force cancel (the
  // interpolation and the spreading share their weights). Without the density
  // the loads would miss the difference, here about 0.3 of the force.
  const long n = 50;
  const auto gr = ring_grid(n);
  std::vector<double> rho(static_cast<std::size_t>(n * n));
  for (long j = 0; j < n; ++j)
    for (long i = 0; i < n; ++i)
      rho[static_cast<std::size_t>(j * n + i)] = 1.0 + 0.3 * std::sin(0.2 * i + 0.1 * j);
  const double dt = 0.01, factor = 2.0 / dt, dv = gr.geometry.cell_volume();
  for (bool cg : {false, true}) {
    ibm::DirectForcing f(gr, {Kernel::roma3, 20, 1e-6, cg}, MPI_COMM_WORLD);
    f.set_markers(ring(63));
    std::vector<double> u(static_cast<std::size_t>(n * n), 1.0), v(u.size(), 0.0);
    const std::vector<double> u0 = u, v0 = v;
    f.apply({u.data(), v.data(), nullptr}, 0.0, 1.0, factor, dt, rho.data());
    double fluid[2] = {0, 0}, plain = 0;  // the fluid's force; without the density
    for (std::size_t x = 0; x < u.size(); ++x) {
      fluid[0] += factor * rho[x] * (u[x] - u0[x]) * dv;
      fluid[1] += factor * rho[x] * (v[x] - v0[x]) * dv;
      plain += factor * (u[x] - u0[x]) * dv;
    }
    const auto loads = f.take_loads();
    INFO("cg " << cg << ": fluid " << fluid[0] << ", " << fluid[1] << "; bodies " << loads[0] << ", "
               << loads[1]);
    CHECK(std::abs(loads[0] + fluid[0]) <= 1e-12 * std::abs(fluid[0]));
    CHECK(std::abs(loads[1] + fluid[1]) <= 1e-12 * std::abs(fluid[0]));
    CHECK(std::abs(plain - fluid[0]) > 0.01 * std::abs(fluid[0]));  // the density matters here
  }
}

TEST_CASE("conjugate gradients stop where markers sharing a stencil ask for opposite velocities",
          "[immersed][ibm]") {
  // Two markers at one point, one asking for +1 and one for -1, in a fluid at
  // rest: the right-hand side lies in I S's null space, <p, I S p> = 0 at the
  // first step. The solver must stop there (the least-squares answer: no
  // force), not divide by zero.
  const long n = 20;
  const auto gr = ring_grid(n);
  ibm::MarkerSet s;
  s.bodies = {{{0, 0, 0}, {0, 0, 0}}};
  // (Inside the grid, which spans -0.5 to -0.1: before 2026-12-05 the two
  // markers sat outside it, where their stencils were empty.)
  s.markers.push_back({{-0.313, -0.307, 0}, {1, 0, 0}, 1.0, 0});
  s.markers.push_back({{-0.313, -0.307, 0}, {-1, 0, 0}, 1.0, 0});
  ibm::DirectForcing f(gr, {Kernel::roma3, 50, 1e-6, true}, MPI_COMM_WORLD);
  f.set_markers(s);
  std::vector<double> u(static_cast<std::size_t>(n * n), 0.0), v(u.size(), 0.0);
  const auto r = f.apply({u.data(), v.data(), nullptr}, 0.0, 1.0, 1.0, 1.0);
  CHECK(r.slip == Approx(1.0).epsilon(1e-12));  // no velocity pleases both
  for (double x : u) CHECK(x == 0.0);
  const auto loads = f.take_loads();
  for (double l : loads) CHECK(std::isfinite(l));
}

// A fluid velocity that is not finite at the markers: the slip, NaN, read as
// converged (!(NaN > tolerance)) and the series' maxima dropped it; the
// forcing went on without a word until the fluid's own check (found by
// review, 2026-12-05). It now stops there, with both solvers.
TEST_CASE("the forcing stops on a fluid velocity that is not finite", "[immersed][ibm]") {
  const long n = 20;
  const auto gr = ring_grid(n);
  for (bool cg : {false, true}) {
    ibm::MarkerSet s;
    s.bodies = {{{0, 0, 0}, {0, 0, 0}}};
    s.markers.push_back({{-0.313, -0.307, 0}, {1, 0, 0}, 1.0, 0});  // inside the grid, -0.5 to -0.1
    ibm::DirectForcing f(gr, {Kernel::roma3, 50, 1e-6, cg}, MPI_COMM_WORLD);
    f.set_markers(s);
    std::vector<double> u(static_cast<std::size_t>(n * n), std::nan("")), v(u.size(), 0.0);
    CHECK_THROWS_WITH(f.apply({u.data(), v.data(), nullptr}, 0.0, 1.0, 1.0, 1.0),
                      Catch::Contains("not finite"));
  }
}

namespace {
// The forcing on an n^dims grid whose points are dealt out to the world's
// ranks (scattered: by (i + 2 j + 3 k) mod ranks, so every stencil lies on
// several; or in slabs along x, so some do and some do not), against one
// rank holding all of them (MPI_COMM_SELF), from a non-uniform stream: the
// number of points whose forced velocity differs, and of loads that differ.
long forcing_differences(int dims, bool scattered, ibm::ForcingParams params) {
  const long n = 20, nz = dims == 3 ? n : 1;
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const auto at = [n](const std::array<long, 3>& x) { return (x[2] * n + x[1]) * n + x[0]; };
  const auto mine = [=](const std::array<long, 3>& x) {
    return (scattered ? (x[0] + 2 * x[1] + 3 * x[2]) % size : x[0] * size / n) == rank;
  };
  const auto forcing = [&](bool dealt, MPI_Comm comm) {
    ibm::DirectForcing::Grid gr;
    gr.geometry = grid(0.05, n, dims);
    for (int c = 0; c < dims; ++c) {
      ibm::DirectForcing::Points p;
      p.index = [=](const std::array<long, 3>& x) {
        if (x[0] < 0 || x[0] >= n || x[1] < 0 || x[1] >= n || x[2] < 0 || x[2] >= nz) return -1L;
        return dealt && !mine(x) ? -1L : at(x);
      };
      gr.components.push_back(p);
    }
    auto f = std::make_unique<ibm::DirectForcing>(gr, params, comm);
    ibm::MarkerSet s;
    s.bodies = {{{0, 0, 0}, {0, 0, 0}}};
    const double z = dims == 3 ? 1.0 : 0.0;
    s.markers.push_back({{0.0123, -0.0371, 0.0219 * z}, {0.1, 0, 0}, 1.0, 0});
    s.markers.push_back({{-0.0512, 0.0077, -0.0333 * z}, {0, 0.1, 0}, 0.9, 0});
    s.markers.push_back({{0.0301, 0.0444, -0.0101 * z}, {0, 0, 0.1 * z}, 1.1, 0});
    s.markers.push_back({{-0.3021, -0.2544, 0.1101 * z}, {0.05, 0, 0}, 1.0, 0});  // in a slab of its own
    f->set_markers(s);
    return f;
  };
  std::array<std::vector<double>, 3> one, many;
  for (int c = 0; c < dims; ++c) {
    one[c].resize(static_cast<std::size_t>(n * n * nz));
    for (long k = 0; k < nz; ++k)
      for (long j = 0; j < n; ++j)
        for (long i = 0; i < n; ++i)
          one[c][static_cast<std::size_t>(at({i, j, k}))] =
              std::sin(0.3 * i + c) * std::cos(0.2 * j - 0.1 * k);
    many[c] = one[c];
  }
  auto serial = forcing(false, MPI_COMM_SELF), dealt = forcing(true, MPI_COMM_WORLD);
  serial->apply({one[0].data(), one[1].data(), one[2].data()}, 0.0, 1.0, 1.0, 1.0);
  dealt->apply({many[0].data(), many[1].data(), many[2].data()}, 0.0, 1.0, 1.0, 1.0);
  long differ = 0;
  for (int c = 0; c < dims; ++c)
    for (long k = 0; k < nz; ++k)
      for (long j = 0; j < n; ++j)
        for (long i = 0; i < n; ++i) {
          const auto x = static_cast<std::size_t>(at({i, j, k}));
          if (mine({i, j, k}) && one[c][x] != many[c][x]) ++differ;
        }
  const auto a = serial->take_loads(), b = dealt->take_loads();
  for (std::size_t k = 0; k < a.size(); ++k) differ += a[k] != b[k];
  return differ;
}
}  // namespace

TEST_CASE("the forcing gives the same bits however the ranks share the grid's points",
          "[immersed][ibm][mpi]") {
  // The stencils' sums in the same order on one rank and on several: the
  // seed's repeated direct forcing (6 iterations) and conjugate gradients,
  // 3D and 2D, every stencil split or some.
  for (const bool scattered : {true, false}) {
    CHECK(forcing_differences(3, scattered, {Kernel::roma3, 6, 1e-12}) == 0);
    CHECK(forcing_differences(3, scattered, {Kernel::peskin4, 30, 1e-12, true}) == 0);
    CHECK(forcing_differences(2, scattered, {Kernel::roma3, 6, 1e-12}) == 0);
  }
}

TEST_CASE("the forcing reads a uniform stream's speed at the markers", "[immersed][ibm]") {
  // A stream of speed U past markers at rest, no forcing iteration: the slip
  // is the interpolated speed, sum_x phi(x - X) U = U (the kernel sums to one
  // on any shift), to the rounding of the weights' products.
  const long n = 20;
  ibm::DirectForcing::Grid gr;
  gr.geometry = grid(0.05, n, 3);
  for (int c = 0; c < 3; ++c) {
    ibm::DirectForcing::Points p;
    p.index = [n](const std::array<long, 3>& x) {
      for (int d = 0; d < 3; ++d)
        if (x[d] < 0 || x[d] >= n) return -1L;
      return (x[2] * n + x[1]) * n + x[0];
    };
    gr.components.push_back(p);
  }
  ibm::MarkerSet s;
  s.bodies = {{{0, 0, 0}, {0, 0, 0}}};
  s.markers.push_back({{0.0123, -0.0371, 0.0219}, {0, 0, 0}, 1.0, 0});
  s.markers.push_back({{0.1, 0.1, 0.1}, {0, 0, 0}, 1.0, 0});
  for (const double speed : {1.0, 0.0371, 1e-9, 3e4}) {
    ibm::DirectForcing f(gr, {Kernel::peskin4, 0, 1e-6}, MPI_COMM_SELF);
    f.set_markers(s);
    std::vector<double> u(static_cast<std::size_t>(n * n * n), speed), zero(u.size(), 0.0);
    const auto r = f.apply({u.data(), zero.data(), zero.data()}, 0.0, 1.0, 1.0, 1.0);
    CHECK(r.slip == Approx(speed).epsilon(2e-15));  // measured at most 2.2e-16
  }
}
