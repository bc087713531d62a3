// Checkpoints in a run directory are ordered by window number: the names'
// six digits grow to seven at window 10^6, where text order would put
// window_1000000 first (pruned as soon as written, and never `latest`).
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "coflow/run_directory.hpp"

namespace fs = std::filesystem;

TEST_CASE("complete checkpoints come in window order past window 999999", "[run_directory]") {
  const fs::path dir = fs::temp_directory_path() / ("coflow_checkpoints_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  for (const char* n :
       {"window_999999", "window_1000000", "window_000100", "window_1000001.partial", "other"})
    fs::create_directories(dir / "checkpoints" / n);
  std::ofstream(dir / "checkpoints" / "window_000200") << "a file, not a checkpoint\n";
  const auto all = coflow::coupler::complete_checkpoints(dir.string());
  REQUIRE(all.size() == 3);
  CHECK(fs::path(all[0]).filename() == "window_000100");
  CHECK(fs::path(all[1]).filename() == "window_999999");
  CHECK(fs::path(all[2]).filename() == "window_1000000");
  CHECK(coflow::coupler::checkpoint_window(all[2]) == 1000000);
  CHECK(coflow::coupler::checkpoint_window((dir / "checkpoints" / "window_1000001.partial").string()) == -1);
  CHECK(coflow::coupler::checkpoint_window("window_") == -1);
  fs::remove_all(dir);
}
