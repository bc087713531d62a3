// The particle store moves every attribute together: compaction, sorting by id,
// and rows for migration and ghosts (only the attributes that travel with
// them; the others arrive value-initialised).
#include <catch2/catch.hpp>

#include "particles/store/particle_store.hpp"

using namespace coflow::particles::store;

namespace {
struct Pair {
  double a = 0.0, b = 0.0;
};
}  // namespace

template <>
struct coflow::particles::store::Codec<Pair> {
  static constexpr std::size_t doubles = 2;
  static void put(const Pair& p, double* out) {
    out[0] = p.a;
    out[1] = p.b;
  }
  static Pair get(const double* in) { return {in[0], in[1]}; }
};

namespace {
// Three particles with ids 30, 10, 20 and a distinct value in every attribute.
void fill(ParticleStore& s, std::vector<double>& torque, std::vector<Pair>& pair, std::vector<char>& flag) {
  for (int n = 0; n < 3; ++n) {
    const std::size_t i = s.append();
    auto& a = s.arrays();
    a.id[i] = 30 - 10 * ((n + 1) % 3);  // 20, 10, 30... then permuted below
    a.species[i] = n;
    for (int d = 0; d < 3; ++d) {
      a.x[3 * i + d] = n + 0.1 * d;
      a.v[3 * i + d] = -n - 0.1 * d;
      a.force[3 * i + d] = 100 + n;
      torque[3 * i + d] = 200 + n;
    }
    a.radius[i] = 1.0 + n;
    pair[i] = {double(n), -double(n)};
    flag[i] = 1;
  }
}
}  // namespace

TEST_CASE("the particle store keeps and sorts every attribute together", "[particles]") {
  coflow::particles::ParticleArrays arrays;
  std::vector<double> torque;
  std::vector<Pair> pair;
  std::vector<char> flag;
  ParticleStore s(arrays);
  s.add("torque", 3, stays, torque);
  s.add("pair", 1, migrates, pair);
  s.add("flag", 1, migrates, flag);
  fill(s, torque, pair, flag);
  s.check_sizes();
  REQUIRE(s.arrays().id == std::vector<std::int64_t>{20, 10, 30});
  s.sort_by_id();
  REQUIRE(s.arrays().id == std::vector<std::int64_t>{10, 20, 30});
  REQUIRE(s.arrays().species == std::vector<std::int32_t>{1, 0, 2});
  REQUIRE(torque[3] == 200.0);   // particle 20 (n = 0) is now second
  REQUIRE(pair[0].a == 1.0);
  s.keep({1, 0, 1});
  s.check_sizes();
  REQUIRE(s.arrays().id == std::vector<std::int64_t>{10, 30});
  REQUIRE(s.arrays().x[3] == 2.0);
  REQUIRE(pair[1].b == -2.0);
  REQUIRE(torque.size() == 6);
}

TEST_CASE("migration rows carry what migrates; ghost rows what ghosts need", "[particles]") {
  coflow::particles::ParticleArrays a0, a1;
  std::vector<double> t0, t1;
  std::vector<Pair> p0, p1;
  std::vector<char> f0, f1;
  ParticleStore from(a0), to(a1);
  from.add("torque", 3, stays, t0);
  from.add("pair", 1, migrates, p0);
  from.add("flag", 1, migrates, f0);
  to.add("torque", 3, stays, t1);
  to.add("pair", 1, migrates, p1);
  to.add("flag", 1, migrates, f1);
  fill(from, t0, p0, f0);
  // id, species, x, v, w, radius, mass, inertia: 14; + force 3, pair 2, flag 1.
  REQUIRE(from.row_doubles(ghosts) == 14);
  REQUIRE(from.row_doubles(migrates) == 20);
  std::vector<double> rows;
  from.pack(2, migrates, rows);
  from.pack(1, ghosts, rows);
  to.unpack(rows.data(), migrates);
  to.unpack(rows.data() + 20, ghosts);
  to.check_sizes();
  const auto& a = to.arrays();
  REQUIRE(a.id == std::vector<std::int64_t>{30, 10});
  REQUIRE(a.x[0] == 2.0);
  REQUIRE(a.v[5] == -1.0 - 0.1 * 2);
  REQUIRE(a.force[0] == 102.0);   // migrated: its force came along
  REQUIRE(a.force[3] == 0.0);     // ghost: no force
  REQUIRE(p1[0].b == -2.0);
  REQUIRE(p1[1].a == 0.0);
  REQUIRE(f1 == std::vector<char>{1, 0});
  REQUIRE(t1 == std::vector<double>(6, 0.0));  // torque stays behind
  REQUIRE_THROWS(to.unpack_all(std::vector<double>(7, 0.0), migrates));
}
