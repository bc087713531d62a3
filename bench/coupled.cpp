// Benchmark: where the wall time of a coupled run goes.
//
//   build/bin/bench-coupled [CONFIG_DIR]
//
// Runs, through the launcher (three executables), the settling sphere E2
// (configs/validation/psm_settling_sphere_e2.yaml, shortened to 0.15 s) and the
// sand-production demo (configs/sand_production.yaml, shortened to 0.01 s), and
// reads each run's summary.json. For each it prints the share of the wall time
// spent computing in the fluid, the particles and the immersed component, and in
// coupling: time inside exchange calls that is not waiting for a partner
// (packing, copying, MPI overhead), summed over the components. Waiting is the
// serial dependency of serial-explicit coupling (the fluid cannot step before
// it has the solid cells), i.e. load imbalance, and is printed separately.
//
// Last line: RESULT fluid_pct=... particles_pct=... immersed_pct=... coupling_pct=... (for E2)
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

namespace {

struct Split {
  double wall = 0, fluid = 0, particles = 0, immersed = 0, coupling = 0, waiting = 0;
};

// The launcher binary sits next to this one.
std::string launcher(const char* argv0) {
  return (std::filesystem::absolute(argv0).parent_path() / "coflow").string();
}

Split run(const std::string& coflow, const std::string& config, const std::string& out, double end_time) {
  std::filesystem::remove_all(out);
  const std::string cmd = fmt::format("'{}' run '{}' --set run.output.dir='{}' --set run.end_time={} "
                                      "--set run.output.every={} > '{}.log' 2>&1",
                                      coflow, config, out, end_time, end_time, out);
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
    // exchange_s is the time inside exchange calls not spent waiting; wait_s the
    // time blocked on a partner.
    const double compute = v["wall_s"].as<double>() - v["exchange_s"].as<double>() - v["wait_s"].as<double>() -
                           v["io_s"].as<double>();
    const double overhead = v["exchange_s"].as<double>();
    if (name == "fluid") r.fluid = compute;
    if (name == "particles") r.particles = compute;
    if (name == "immersed") r.immersed = compute;
    r.coupling += overhead * ranks;
    r.waiting += v["wait_s"].as<double>() * ranks;
    ranks_total += ranks;
  }
  r.coupling /= ranks_total;  // per rank on average
  r.waiting /= ranks_total;
  return r;
}

void print(const char* name, const Split& s) {
  std::printf("%-18s wall %7.2f s | fluid %5.1f %% | particles %5.1f %% | immersed %5.1f %% | coupling %4.1f %% | "
              "waiting %5.1f %%\n",
              name, s.wall, 100 * s.fluid / s.wall, 100 * s.particles / s.wall, 100 * s.immersed / s.wall,
              100 * s.coupling / s.wall, 100 * s.waiting / s.wall);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string configs = argc > 1 ? argv[1] : "configs";
    const std::string coflow = launcher(argv[0]);
    const auto tmp = std::filesystem::temp_directory_path();
    std::printf("bench-coupled: shares of the wall time (compute per component; coupling = exchange time not spent "
                "waiting, per rank; waiting = serial dependency)\n");
    const Split e2 = run(coflow, configs + "/validation/psm_settling_sphere_e2.yaml",
                         (tmp / "coflow-bench-e2").string(), 0.15);
    print("settling sphere E2", e2);
    const Split sand = run(coflow, configs + "/sand_production.yaml", (tmp / "coflow-bench-sand").string(), 0.01);
    print("sand production", sand);
    std::printf("RESULT fluid_pct=%.1f particles_pct=%.1f immersed_pct=%.1f coupling_pct=%.2f\n",
                100 * e2.fluid / e2.wall, 100 * e2.particles / e2.wall, 100 * e2.immersed / e2.wall,
                100 * e2.coupling / e2.wall);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench-coupled: %s\n", e.what());
    return 1;
  }
  return 0;
}
