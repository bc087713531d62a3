// The benchmarks' command lines, read by CLI11: `--help` prints the usage,
// and a bad argument stops the program with what is wrong, before MPI starts.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdlib>
#include <string>

namespace coflow::bench {

// Parses argv into `app`'s options: exits 0 after --help, 2 on a bad argument
// (CLI11's message names the argument and what it expects).
inline void parse_args(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    std::exit(app.exit(e) == 0 ? 0 : 2);
  }
}

// The positional count of steps (1 to 1e8), its default shown in the usage.
template <class T>
void add_steps(CLI::App& app, T& steps, const std::string& what) {
  app.add_option("steps", steps, what)->check(CLI::Range(1, 100000000))->capture_default_str();
}

}  // namespace coflow::bench
