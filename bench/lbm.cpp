// Benchmark: lbm D3Q19 BGK (standard, no force), periodic cube, 1 rank.
//
//   build/bin/bench-lbm [steps]
//   mpirun -np 2 build/bin/bench-lbm [steps]     two ranks, one per core
//
// On 2 ranks it prints instead the two-core figures: BGK 256^3 cut in two
// slabs (MLUPS, max over the ranks per step) against the roofline of both
// cores copying at once (the socket's bandwidth, measured right before and
// after), and the strong scaling from 1 rank (rank 0 alone, same grid, same
// run) to 2.
//
// Prints MLUPS (million lattice-cell updates per second) at 128^3 and 256^3, the
// copy bandwidth of this machine measured in the same run, and the roofline.
// The kernel reads 19 populations and writes 19 with streaming stores (no
// write-allocate): 304 B per cell update, so roofline MLUPS = bandwidth / 304 B,
// with the bandwidth of a copy using the same loads and streaming stores. A
// shared host's bandwidth drifts by tens of per cent within a minute, so every
// timed step is paired with copies right before and after it (best of two
// passes each), and its fraction taken against the larger of the two; the figures are the medians
// over the steps (with the range).
// Last line: RESULT mlups=... roofline_mlups=... fraction=... (256^3, medians)
#include <mpi.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <chrono>
#include <string>
#include <thread>
#include <utility>
#include <vector>
#if defined(__AVX__)
#include <immintrin.h>
#endif

#include <fmt/format.h>

#include "bench_args.hpp"
#include "bench_util.hpp"
#include "coflow/catalog.hpp"
#include "coflow/log.hpp"
#include "coflow/memory.hpp"
#include "coflow/trace.hpp"
#include "fluid/driver.hpp"
#include "fluid/fluid_solver.hpp"
#include "fluid/lbm/collision.hpp"
#include "fluid/lbm/lattice.hpp"
#include "fluid/schema.hpp"

using namespace coflow;
using coflow::HugeVector;

namespace {

using coflow::bench::median;
using coflow::bench::sleepy_barrier;

// Copy bandwidth with the same store kind as the kernel: loads and streaming
// (non-temporal) stores, traffic = 2 x the array size.
struct Copy {
  static constexpr std::size_t n = std::size_t(1) << 26;  // 512 MiB per array
  HugeVector<double> a = HugeVector<double>(n, 1.0), b = HugeVector<double>(n, 0.0);
  double once() {
    const double t0 = coupler::now();
#if defined(__AVX__)
    for (std::size_t i = 0; i < n; i += 4) _mm256_stream_pd(b.data() + i, _mm256_load_pd(a.data() + i));
    _mm_sfence();
#else
    std::copy(a.begin(), a.end(), b.begin());
#endif
    const double t = coupler::now() - t0;
    a[0] = b[n - 1];
    return 2.0 * n * sizeof(double) / t;
  }
  double best(int repeats) {
    double bw = 0.0;
    for (int r = 0; r < repeats; ++r) bw = std::max(bw, once());
    return bw;
  }
};

constexpr double bytes_per_update = 304.0;
// Two colours: 2 x 19 pulled loads and 2 x 19 stores of 8 B, and the colour
// field written and read once (16 B): the least a fused colour-gradient update
// moves. lbm's colour kernel takes the colour field from the pulled
// populations in one pass and pulls them again to collide in a second
// (another 304 B loaded, and 304 B of write-allocate: about twice this).
constexpr double two_phase_bytes = 624.0;

// MLUPS of each step and the roofline (MLUPS) beside it.
struct Steps {
  std::vector<double> mlups, roof, fraction;
  void add(double m, double r) {
    mlups.push_back(m);
    roof.push_back(r);
    fraction.push_back(m / r);
  }
  std::string describe() const {
    const auto [lo, hi] = std::minmax_element(fraction.begin(), fraction.end());
    return fmt::format("{:.1f} MLUPS, roofline beside it {:.1f}: fraction {:.2f} ({:.2f}-{:.2f} over {} steps)",
                       median(mlups), median(roof), median(fraction), *lo, *hi, fraction.size());
  }
};

// general: TRT with a Guo body force (the general kernel) instead of BGK
// without force (the lean kernel); packed: populations one after another
// instead of lbm::spaced_stride apart (fluid.lbm.layout).
// two_phase: red and blue populations (colour gradient, BGK, a droplet in the
// box), whose roofline counts two_phase_bytes per update.
std::string bench_config(long n, bool general, bool packed, bool two_phase) {
  return fmt::format(R"(
run: {{name: bench-lbm, end_time: 1.0}}
domain: {{lower: [0, 0, 0], upper: [{0}, {0}, {0}], cells: [{1}, {1}, {1}], periodic: [true, true, true]}}
fluid:
  solver: lbm
  density: 1000.0
  viscosity: 1.0e-6
  initial: {{field: taylor-green, amplitude: 1.0e-4{5}}}
  body_force: [{2}, 0.0, 0.0]
  lbm: {{lattice: D3Q19, formulation: standard, tau: 0.8, collision: {3}, layout: {4}}}
{6}
)",
                                       n * 1e-3, n, general ? 1.0e-3 : 0.0, general ? "trt" : "bgk",
                                       packed ? "packed" : "auto",
                                       two_phase ? fmt::format(", phase: [{{fill: {{phase: blue}}}}, {{sphere: "
                                                               "{{centre: [{0}, {0}, {0}], radius: {1}, phase: red}}}}]",
                                                               n * 5e-4, n * 2.5e-4)
                                                 : "",
                                       two_phase ? "  two_phase: {surface_tension: 1.0e-6}" : "");
}

Steps mlups(long n, int steps, bool general, bool packed, Copy& copy, bool two_phase = false) {
  const std::string text = bench_config(n, general, packed, two_phase);
  const config::Config cfg = config::parse_config_node(YAML::Load(text), "bench", catalog());
  const fluid::FluidParams params = fluid::read_params(cfg);
  const coupler::Decomposition dec({n, n, n}, 1, {1, 1, 1}, {true, true, true});
  const auto solver = fluid::make_solver({cfg, params, dec, 0, MPI_COMM_WORLD});
  const double dt = solver->time_step();
  solver->advance(2 * dt);  // warm-up (first touch of the pages)
  Steps out;
  double before = copy.best(2);
  for (int s = 0; s < steps; ++s) {
    const double t0 = coupler::now();
    solver->advance(dt);
    const double t = coupler::now() - t0;
    const double after = copy.best(2);
    out.add(static_cast<double>(n) * n * n / t / 1e6,
            std::max(before, after) / (two_phase ? two_phase_bytes : bytes_per_update) / 1e6);
    before = after;
  }
  return out;
}

// The kernel's memory pattern without its arithmetic: two arrays of 19
// populations on a padded 256^3 grid, each cell pulling its 19 values from the
// neighbours (19 streams with offsets) and writing them with streaming stores
// (19 more). The ceiling this pattern reaches on this core: the gap between it
// and the copy bandwidth is the cost of the 38 streams; the gap between it and
// the solver is the cost of the collision.
double pattern_mlups(long n, int steps) {
  using L = fluid::lbm::D3Q19;
  constexpr int Q = L::Q;
  const long P0 = n + 8, P1 = n + 2, P2 = n + 2, N = P0 * P1 * P2;
  HugeVector<double> a(Q * N, 1e-3), b(Q * N, 0.0);
  long off[Q];
  for (int q = 0; q < Q; ++q) off[q] = L::e[q][0] + P0 * (L::e[q][1] + P1 * L::e[q][2]);
  double best = 0.0;
  for (int s = 0; s < steps; ++s) {
    const double t0 = coupler::now();
    for (long k = 1; k <= n; ++k)
      for (long j = 1; j <= n; ++j) {
        const long base = (k * P1 + j) * P0 + 8;  // rows start on a cache line
        for (long i = 0; i < n; i += 8) {  // whole cache lines, both halves stored together
          const long x = base + i;
#if defined(__AVX__)
#pragma GCC unroll 19
          for (int q = 0; q < Q; ++q) {
            const __m256d lo = _mm256_loadu_pd(a.data() + q * N + x - off[q]);
            const __m256d hi = _mm256_loadu_pd(a.data() + q * N + x + 4 - off[q]);
            _mm256_stream_pd(b.data() + q * N + x, lo);
            _mm256_stream_pd(b.data() + q * N + x + 4, hi);
          }
#else
          for (int q = 0; q < Q; ++q)
            for (int w = 0; w < 8; ++w) b[q * N + x + w] = a[q * N + x + w - off[q]];
#endif
        }
      }
#if defined(__AVX__)
    _mm_sfence();
#endif
    best = std::max(best, static_cast<double>(n) * n * n / (coupler::now() - t0) / 1e6);
    std::swap(a, b);
  }
  return best;
}

// The colour-gradient kernel's memory pattern without its arithmetic, in its
// layout (red and blue populations of a cell side by side, 19 streams), on a
// n^3 block with one ghost layer (no exchange): a first pass pulls the 19 pairs of four cells and
// stores their colour sum, a second reads the 18 neighbours' colours, pulls
// the pairs again and stores them (ordinary stores, as the kernel's). The
// ceiling the two-phase kernel can reach with this pattern on this core.
double two_phase_pattern_mlups(long n, int steps) {
  using L = fluid::lbm::D3Q19;
  constexpr int Q = L::Q;
  const long P0 = n + 2, P1 = n + 2, N = P0 * P1 * (n + 2);
  HugeVector<double> a(2 * Q * N, 1e-3), b(2 * Q * N, 0.0), phi(N, 0.0);
  long off[Q];
  for (int q = 0; q < Q; ++q) off[q] = L::e[q][0] + P0 * (L::e[q][1] + P1 * L::e[q][2]);
  using fluid::lbm::Vec4, fluid::lbm::detail::get;
  const auto put = fluid::lbm::detail::put<false>;
  double best = 0.0;
  for (int s = 0; s < steps; ++s) {
    const double t0 = coupler::now();
    for (int pass = 0; pass < 2; ++pass)
      for (long k = 1; k <= n; ++k)
        for (long j = 1; j <= n; ++j)
          for (long i = 1; i + 4 <= n + 1; i += 4) {
            const long x = (k * P1 + j) * P0 + i;
            Vec4 sum = {0.0, 0.0, 0.0, 0.0};
            if (pass == 1)
              for (int q = 1; q < Q; ++q) sum += get(phi.data() + x + off[q]);
#pragma GCC unroll 19
            for (int q = 0; q < Q; ++q) {
              const double* p = a.data() + 2 * (q * N + x - off[q]);
              const Vec4 lo = get(p), hi = get(p + 4);
              fluid::lbm::prefetch_pulled(p + fluid::lbm::prefetch_ahead);
              if (pass == 0) {
                sum += lo - hi;
              } else {
                put(b.data() + 2 * (q * N + x), lo + sum);
                put(b.data() + 2 * (q * N + x) + 4, hi);
              }
            }
            if (pass == 0) put(phi.data() + x, sum);
          }
    best = std::max(best, static_cast<double>(n) * n * n / (coupler::now() - t0) / 1e6);
    std::swap(a, b);
  }
  return best;
}

// Bandwidth of all ranks of `comm` copying at once (bytes/s in all): best of
// `repeats`, each the slowest rank's time.
double copy_together(Copy& copy, MPI_Comm comm, int repeats) {
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  double best = 0.0;
  for (int r = 0; r < repeats; ++r) {
    MPI_Barrier(comm);
    const double t0 = coupler::now();
    copy.once();
    double t = coupler::now() - t0, most = 0.0;
    MPI_Allreduce(&t, &most, 1, MPI_DOUBLE, MPI_MAX, comm);
    best = std::max(best, ranks * 2.0 * Copy::n * sizeof(double) / most);
  }
  return best;
}

// Median seconds per BGK step of an n^3 periodic box cut over the ranks of
// `comm` (slowest rank), and the copy bandwidth of all of them at once,
// the larger of before and after.
std::pair<double, double> step_and_copy(long n, int steps, MPI_Comm comm, Copy& copy) {
  int ranks = 1, rank = 0;
  MPI_Comm_size(comm, &ranks);
  MPI_Comm_rank(comm, &rank);
  const config::Config cfg = config::parse_config_node(YAML::Load(bench_config(n, false, false, false)), "bench",
                                                       catalog());
  const fluid::FluidParams params = fluid::read_params(cfg);
  const coupler::Decomposition dec({n, n, n}, ranks, {1, 1, ranks}, {true, true, true});
  const auto solver = fluid::make_solver({cfg, params, dec, rank, comm});
  const double dt = solver->time_step();
  solver->advance(2 * dt);
  const double before = copy_together(copy, comm, 2);
  std::vector<double> times;
  for (int s = 0; s < steps; ++s) {
    MPI_Barrier(comm);
    const double t0 = coupler::now();
    solver->advance(dt);
    double t = coupler::now() - t0, most = 0.0;
    MPI_Allreduce(&t, &most, 1, MPI_DOUBLE, MPI_MAX, comm);
    times.push_back(most);
  }
  return {median(times), std::max(before, copy_together(copy, comm, 2))};
}

// mpirun -np 2: the two-core figures (see the top of this file).
void two_ranks(int steps, Copy& copy) {
  const long n = 256;
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm solo;
  MPI_Comm_split(MPI_COMM_WORLD, rank == 0 ? 0 : MPI_UNDEFINED, 0, &solo);
  std::pair<double, double> one{0, 0};
  if (solo != MPI_COMM_NULL) {
    one = step_and_copy(n, steps, solo, copy);
    MPI_Comm_free(&solo);
  }
  sleepy_barrier(MPI_COMM_WORLD);
  const auto two = step_and_copy(n, steps, MPI_COMM_WORLD, copy);
  if (rank != 0) return;
  const double cells = static_cast<double>(n) * n * n;
  const double m1 = cells / one.first / 1e6, m2 = cells / two.first / 1e6;
  const double roof1 = one.second / bytes_per_update / 1e6, roof2 = two.second / bytes_per_update / 1e6;
  std::printf("D3Q19 BGK 256^3 periodic, 1 rank (rank 0 alone): %.1f MLUPS, roofline of one core copying %.1f "
              "(%.1f GB/s): fraction %.2f\n", m1, roof1, one.second / 1e9, m1 / roof1);
  std::printf("D3Q19 BGK 256^3 periodic, 2 ranks (slabs of 256 x 256 x 128): %.1f MLUPS, roofline of both cores "
              "copying at once %.1f (%.1f GB/s): fraction %.2f\n", m2, roof2, two.second / 1e9, m2 / roof2);
  std::printf("strong scaling 1 -> 2 ranks: speed-up %.2f (efficiency %.2f); the socket's bandwidth over one "
              "core's: %.2f\n", m2 / m1, m2 / m1 / 2.0, two.second / one.second);
  std::printf("RESULT mlups_2=%.2f roofline_2=%.2f fraction_2=%.3f speedup=%.2f\n", m2, roof2, m2 / roof2, m2 / m1);
}

}  // namespace

int main(int argc, char** argv) {
  int steps = 10;
  CLI::App app{
      "bench-lbm: the lbm kernels' MLUPS against this machine's memory roofline (see bench/lbm.cpp)"};
  coflow::bench::add_steps(
      app, steps, "timed steps of the BGK 256^3 cases (TRT + Guo: half; 128^3: twice; two-phase: 3)");
  coflow::bench::parse_args(app, argc, argv);
  MPI_Init(&argc, &argv);
  log::init("bench", 1);  // rank 1: warnings only
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (size > 2) {  // every rank would run its own cases, fighting over the bandwidth
    std::fprintf(stderr, "bench-lbm: runs on 1 rank, or on 2 (one per core); not on %d\n", size);
    MPI_Finalize();
    return 2;
  }
  Copy copy;
  if (size == 2) {
    two_ranks(steps, copy);
    MPI_Finalize();
    return 0;
  }
  const double bw = copy.best(5);
  const double roof = bw / bytes_per_update / 1e6;
  std::printf("copy bandwidth (1 core, loads + streaming stores), best of 5 at the start: %.2f GB/s\n", bw / 1e9);
  std::printf("bytes per cell update: 304 (D3Q19, A/B arrays: 19 x 8 B loads + 19 x 8 B streaming stores)\n");
  std::printf("roofline at the start: %.1f MLUPS\n", roof);
  const double pattern = pattern_mlups(256, 3);
  std::printf("memory pattern alone (19 pulled loads + 19 streaming stores, no collision) 256^3: %.1f MLUPS (%.0f "
              "%% of the roofline at the start)\n",
              pattern, 100 * pattern / roof);
  std::printf("per step, medians (MLUPS, roofline from the copies just before and after, fraction):\n");
  std::printf("D3Q19 TRT + Guo body force 256^3 periodic, 1 rank: %s\n",
              mlups(256, std::max(3, steps / 2), true, false, copy).describe().c_str());
  std::printf("D3Q19 BGK 128^3 periodic, 1 rank: %s\n", mlups(128, 2 * steps, false, false, copy).describe().c_str());
  std::printf("D3Q19 BGK 256^3 periodic, 1 rank, packed layout: %s\n",
              mlups(256, steps, false, true, copy).describe().c_str());
  const Steps two_phase = mlups(128, 3, false, false, copy, true);
  std::printf(
      "D3Q19 BGK two-phase (colour gradient, a droplet) 128^3 periodic, 1 rank, against %.0f B per update: "
      "%s\n",
      two_phase_bytes, two_phase.describe().c_str());
  const double two_phase_pattern = two_phase_pattern_mlups(128, 3);
  std::printf(
      "two-phase memory pattern alone (two passes: 19 pulled pairs; 18 colours, 19 pulled pairs and 19 "
      "stored, no collision) 128^3: %.1f MLUPS (best of 3); the kernel's best step at %.2f of it\n",
      two_phase_pattern,
      *std::max_element(two_phase.mlups.begin(), two_phase.mlups.end()) / two_phase_pattern);
  const Steps last = mlups(256, steps, false, false, copy);
  std::printf("D3Q19 BGK 256^3 periodic, 1 rank: %s\n", last.describe().c_str());
  std::printf("RESULT mlups=%.2f roofline_mlups=%.2f fraction=%.3f\n", median(last.mlups), median(last.roof),
              median(last.fraction));
  MPI_Finalize();
  return 0;
}
