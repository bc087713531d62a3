// Benchmark: where the wall time of a coupled run goes, and what a coupled
// run costs against its fluid alone.
//
//   build/bin/bench-coupled [CONFIG_DIR]
//
// Runs, through the launcher (three executables):
//  1. the quickstart (configs/quickstart.yaml, 2 + 1 + 1 ranks) coupled with
//     serial-explicit and with parallel-explicit, and its fluid alone
//     (immersed.method none, particles.solver none: the same 2 fluid ranks),
//     three times each, interleaved (this host's speed drifts), and prints the
//     medians and their ratio;
//  2. the settling sphere E2 (configs/validation/psm_settling_sphere_e2.yaml,
//     shortened to 0.15 s) with both schemes, and the sand-production demo
//     (configs/sand_production.yaml, shortened to 0.01 s), reading each run's
//     summary.json: the share of the wall time spent computing in the fluid,
//     the particles and the immersed component, and in coupling: time inside
//     exchange calls that is not waiting for a partner (packing, copying, MPI
//     overhead), averaged over the ranks. Waiting (time blocked on a partner,
//     averaged over the ranks, and the fluid's own) is printed separately.
//
// Last line: RESULT quickstart_ratio=... quickstart_parallel_ratio=... e2_waiting_pct=...
// e2_parallel_waiting_pct=... e2_fluid_waiting_pct=... e2_parallel_fluid_waiting_pct=...
// sand_immersed_pct=... e2_coupling_pct=... sand_coupling_pct=...
#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_args.hpp"
#include "bench_util.hpp"

namespace {

using coflow::bench::median;

struct Split {
  double wall = 0, fluid = 0, particles = 0, immersed = 0, coupling = 0, waiting = 0;
  double fluid_waiting = 0;  // the fluid's own (summary.json: the largest over its ranks)
};

// The launcher binary sits next to this one (found through /proc/self/exe:
// argv[0] holds no directory when the bench is run from the PATH).
std::string launcher(const char*) {
  return (std::filesystem::canonical("/proc/self/exe").parent_path() / "coflow").string();
}

Split run(const std::string& coflow, const std::string& config, const std::string& out, double end_time,
          const std::string& sets = "") {
  std::filesystem::remove_all(out);
  const std::string cmd = fmt::format("'{}' run '{}' --set run.output.dir='{}' --set run.end_time={} "
                                      "--set run.output.every={} {} > '{}.log' 2>&1",
                                      coflow, config, out, end_time, end_time, sets, out);
  if (std::system(cmd.c_str()) != 0) throw std::runtime_error("run failed: see " + out + ".log");
  // summary.json is JSON, which YAML reads.
  const YAML::Node s = YAML::LoadFile(out + "/summary.json");
  Split r;
  r.wall = s["wall_s"].as<double>();
  double ranks_total = 0;
  for (const auto& c : s["components"]) {
    const std::string name = c.first.as<std::string>();
    const auto& v = c.second;
    const double ranks = v["ranks"].as<double>();
    // compute_s: the busiest rank's own wall less its exchange, waiting and
    // I/O; exchange (inside exchange calls, not waiting) and waiting (blocked
    // on a partner) as the means over the component's ranks.
    const double compute = v["compute_s"].as<double>();
    if (name == "fluid") r.fluid = compute, r.fluid_waiting = v["wait_s"].as<double>();  // the largest
    if (name == "particles") r.particles = compute;
    if (name == "immersed") r.immersed = compute;
    r.coupling += v["exchange_mean_s"].as<double>() * ranks;
    r.waiting += v["wait_mean_s"].as<double>() * ranks;
    ranks_total += ranks;
  }
  r.coupling /= ranks_total;  // per rank on average over all ranks
  r.waiting /= ranks_total;
  return r;
}

void print(const char* name, const Split& s) {
  std::printf("%-18s wall %7.2f s | fluid %5.1f %% | particles %5.1f %% | immersed %5.1f %% | coupling %4.1f %% | "
              "waiting %5.1f %% (the fluid's %4.1f %%)\n",
              name, s.wall, 100 * s.fluid / s.wall, 100 * s.particles / s.wall, 100 * s.immersed / s.wall,
              100 * s.coupling / s.wall, 100 * s.waiting / s.wall, 100 * s.fluid_waiting / s.wall);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    std::string configs = "configs";
    CLI::App app{"bench-coupled: a coupled run against its fluid alone (see bench/coupled.cpp)"};
    app.add_option("configs", configs, "the configs directory")
        ->check(CLI::ExistingDirectory)
        ->capture_default_str();
    coflow::bench::parse_args(app, argc, argv);
    const std::string coflow = launcher(argv[0]);
    const auto tmp = std::filesystem::temp_directory_path();
    const std::string qs = configs + "/quickstart.yaml", qs_out = (tmp / "coflow-bench-quickstart").string();
    std::vector<double> serial, parallel, alone;
    for (int rep = 0; rep < 3; ++rep) {
      serial.push_back(run(coflow, qs, qs_out, 0.8).wall);
      parallel.push_back(run(coflow, qs, qs_out, 0.8, "--set coupling.scheme=parallel-explicit").wall);
      alone.push_back(run(coflow, qs, qs_out, 0.8, "--set immersed.method=none --set particles.solver=none").wall);
    }
    const double ms = median(serial), mp = median(parallel), ma = median(alone);
    std::printf("bench-coupled: quickstart (2 + 1 + 1 ranks), medians of 3 interleaved runs:\n"
                "  fluid alone %.2f s | serial-explicit %.2f s (%.2fx) | parallel-explicit %.2f s (%.2fx)\n",
                ma, ms, ms / ma, mp, mp / ma);
    std::printf("bench-coupled: shares of the wall time (compute per component; coupling = exchange time not spent "
                "waiting, per rank; waiting = time blocked on a partner, per rank)\n");
    const std::string e2cfg = configs + "/validation/psm_settling_sphere_e2.yaml";
    const Split e2 = run(coflow, e2cfg, (tmp / "coflow-bench-e2").string(), 0.15);
    print("E2 serial", e2);
    const Split e2p = run(coflow, e2cfg, (tmp / "coflow-bench-e2").string(), 0.15,
                          "--set coupling.scheme=parallel-explicit");
    print("E2 parallel", e2p);
    const Split sand = run(coflow, configs + "/sand_production.yaml", (tmp / "coflow-bench-sand").string(), 0.01);
    print("sand production", sand);
    std::printf("RESULT quickstart_ratio=%.2f quickstart_parallel_ratio=%.2f e2_waiting_pct=%.1f "
                "e2_parallel_waiting_pct=%.1f e2_fluid_waiting_pct=%.1f e2_parallel_fluid_waiting_pct=%.1f "
                "sand_immersed_pct=%.1f e2_coupling_pct=%.2f sand_coupling_pct=%.2f\n",
                ms / ma, mp / ma, 100 * e2.waiting / e2.wall, 100 * e2p.waiting / e2p.wall,
                100 * e2.fluid_waiting / e2.wall, 100 * e2p.fluid_waiting / e2p.wall,
                100 * sand.immersed / sand.wall, 100 * e2.coupling / e2.wall, 100 * sand.coupling / sand.wall);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench-coupled: %s\n", e.what());
    return 1;
  }
  return 0;
}
