// Reading a whole text file (a run's log, to parse), for the benchmarks that
// run the launcher and read what the components logged.
#pragma once

#include <fstream>
#include <sstream>
#include <string>

namespace coflow::bench {

// The text of a file ("" when it cannot be read).
inline std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace coflow::bench
