#include "particles/dem/bond_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <fstream>
#include <map>
#include <utility>
#include <stdexcept>

#include "coflow/config.hpp"

namespace coflow::particles::dem {

std::vector<BondPair> read_bond_csv(const std::string& path) {
  if (const std::string why = config::file_problem(path); !why.empty())
    throw std::runtime_error(fmt::format("{}: {} (a bond file was expected)", path, why));
  std::ifstream in(path);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot open the bond file", path));
  std::vector<BondPair> pairs;
  std::map<std::pair<std::int64_t, std::int64_t>, int> first_line;
  std::string line;
  int number = 0;
  bool header = false;
  while (std::getline(in, line)) {
    ++number;
    line.erase(std::remove_if(line.begin(), line.end(), [](unsigned char c) { return std::isspace(c); }), line.end());
    if (line.empty() || line[0] == '#') continue;
    if (!header) {
      if (line != "i,j")
        throw std::runtime_error(fmt::format("{}:{}: the first line must be the header i,j (got '{}')", path, number, line));
      header = true;
      continue;
    }
    BondPair b;
    b.line = number;
    const auto comma = line.find(',');
    const char* end = line.data() + line.size();
    const auto r1 = std::from_chars(line.data(), line.data() + std::min(comma, line.size()), b.i);
    const auto r2 = comma == std::string::npos ? std::from_chars_result{line.data(), std::errc::invalid_argument}
                                                : std::from_chars(line.data() + comma + 1, end, b.j);
    if (comma == std::string::npos || r1.ec != std::errc() || r2.ec != std::errc() ||
        r1.ptr != line.data() + comma || r2.ptr != end)
      throw std::runtime_error(fmt::format("{}:{}: expected two particle ids 'i,j' (got '{}')", path, number, line));
    if (b.i < 0 || b.j < 0 || b.i == b.j)
      throw std::runtime_error(
          fmt::format("{}:{}: a bond joins two different particles with ids >= 0 (got {},{})", path, number, b.i, b.j));
    if (b.i > b.j) std::swap(b.i, b.j);
    // A pair twice is an error of the file alone: said at validate, not by
    // the particles after the ranks start (bonds_from_file checks it again).
    if (const auto [at, fresh] = first_line.emplace(std::make_pair(b.i, b.j), number); !fresh)
      throw std::runtime_error(fmt::format("{}:{}: the pair {},{} is listed twice (first on line {})", path, number,
                                           b.i, b.j, at->second));
    pairs.push_back(b);
  }
  if (!header) throw std::runtime_error(fmt::format("{}: empty bond file (expected the header i,j)", path));
  return pairs;
}

}  // namespace coflow::particles::dem
