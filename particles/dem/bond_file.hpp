// Bond files: which particle pairs a bonded DEM run cements. Part of the
// particles schema library (validation reads them).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace coflow::particles::dem {

// A CSV file of bonded pairs (header `i,j`, then one pair of particle ids per
// line; blank lines and lines starting with # are skipped). Each pair comes with
// its line number. Throws "file:line: reason" on anything else.
struct BondPair {
  std::int64_t i = 0, j = 0;
  int line = 0;
};
std::vector<BondPair> read_bond_csv(const std::string& path);

}  // namespace coflow::particles::dem
