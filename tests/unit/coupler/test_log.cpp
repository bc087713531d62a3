// Log files: rank 0 writes logs/<component>.log; another rank writes its
// warnings and errors alone to logs/<component>.<rank>.log, created at its
// first, so that no two ranks append to one file (NFS) and a rank with
// nothing to say leaves no file.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <string>

#include "bench/text_file.hpp"
#include "coflow/log.hpp"

namespace fs = std::filesystem;
using coflow::bench::slurp;

TEST_CASE("a rank other than 0 writes its warnings and errors alone, to a file of its own", "[log]") {
  const fs::path dir = fs::temp_directory_path() / ("coflow_logs_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  coflow::log::init("fluid", 1, dir.string());
  coflow::log::info("a line every rank writes");
  coflow::log::get()->flush();
  CHECK(!fs::exists(dir / "fluid.1.log"));
  coflow::log::warn("rank {} sees {}", 1, 42);
  coflow::log::error("and fails");
  coflow::log::get()->flush();
  const std::string one = slurp(dir / "fluid.1.log");
  CHECK(one.find("[fluid:1] [warning] rank 1 sees 42\n") != std::string::npos);
  CHECK(one.find("[fluid:1] [error] and fails\n") != std::string::npos);
  CHECK(one.find("a line every rank writes") == std::string::npos);
  CHECK(!fs::exists(dir / "fluid.log"));
  coflow::log::init("fluid", 0, dir.string());
  coflow::log::info("rank 0's line");
  coflow::log::get()->flush();
  CHECK(slurp(dir / "fluid.log").find("[fluid:0] [info] rank 0's line\n") != std::string::npos);
  coflow::log::init("coflow", 0);  // the console alone again, for the tests after this one
  fs::remove_all(dir);
}
