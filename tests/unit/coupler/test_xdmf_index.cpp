// run.xdmf from the components' index.csv files (coflow/output.hpp):
// - each snapshot's grid lists the fields its own row names (a restart may
//   write other fields than the run before it);
// - the two components' rank 0 write it concurrently: the read of the indexes
//   and the write wait for the lock on run.xdmf.lock, so the file a writer
//   leaves always holds the row that writer has just indexed. (Without the
//   lock, 2 x 1000 rows from two threads showed no stale file on the 2-core
//   test VM: the race is narrow. The first test case below shows that the
//   writer waits for the lock; the second checks the outcome.)
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "bench/text_file.hpp"
#include "coflow/output.hpp"

namespace fs = std::filesystem;
namespace out = coflow::output;

namespace {

// The attribute names of each <Grid ... GridType="Uniform"> block named `name`.
std::vector<std::vector<std::string>> grid_attributes(const std::string& xdmf, const std::string& name) {
  std::vector<std::vector<std::string>> grids;
  const std::string open = "<Grid Name=\"" + name + "\" GridType=\"Uniform\">";
  for (std::size_t at = xdmf.find(open); at != std::string::npos; at = xdmf.find(open, at + 1)) {
    const std::size_t end = xdmf.find("</Grid>", at);
    std::vector<std::string> attrs;
    for (std::size_t a = xdmf.find("<Attribute Name=\"", at); a < end; a = xdmf.find("<Attribute Name=\"", a + 1)) {
      const std::size_t b = a + 17;
      attrs.push_back(xdmf.substr(b, xdmf.find('"', b) - b));
    }
    grids.push_back(attrs);
  }
  return grids;
}

fs::path fresh_dir(const std::string& tag) {
  const fs::path dir = fs::temp_directory_path() / ("coflow_xdmf_" + tag + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "fluid");
  fs::create_directories(dir / "particles");
  return dir;
}

const out::GridGeometry kGrid{{0.0, 0.0, 0.0}, {0.1, 0.1, 0.1}, {4, 3, 2}};

}  // namespace

TEST_CASE("each snapshot's grid in run.xdmf lists its own row's fields", "[xdmf]") {
  const fs::path dir = fresh_dir("fields");
  out::append_index(dir.string(), "fluid", {0, 0.0, 0}, {"velocity", "pressure"});
  out::append_index(dir.string(), "fluid", {1, 1.0, 0}, {"velocity", "pressure", "vorticity"});
  out::append_index(dir.string(), "particles", {0, 0.0, 5}, {"position", "velocity"});
  out::append_index(dir.string(), "particles", {1, 1.0, 7}, {"position", "radius"});
  out::write_xdmf(dir.string(), kGrid);
  const std::string x = coflow::bench::slurp(dir / "run.xdmf");
  const auto fluid = grid_attributes(x, "fluid");
  REQUIRE(fluid.size() == 2);
  CHECK(fluid[0] == std::vector<std::string>{"velocity", "pressure"});
  CHECK(fluid[1] == std::vector<std::string>{"velocity", "pressure", "vorticity"});
  const auto parts = grid_attributes(x, "particles");
  REQUIRE(parts.size() == 2);
  CHECK(parts[0] == std::vector<std::string>{"id", "species", "velocity"});
  CHECK(parts[1] == std::vector<std::string>{"id", "species", "radius"});
  CHECK(x.find("step_000001.h5:/vorticity") != std::string::npos);
  CHECK(x.find("step_000000.h5:/vorticity") == std::string::npos);
  const auto table = out::read_index((dir / "fluid" / "index.csv").string());
  REQUIRE(table.rows.size() == 2);
  CHECK(table.rows[1].fields.size() == 3);
  fs::remove_all(dir);
}

TEST_CASE("run.xdmf is written only under the lock on run.xdmf.lock", "[xdmf]") {
  const fs::path dir = fresh_dir("lock");
  out::append_index(dir.string(), "fluid", {0, 0.0, 0}, {"velocity"});
  const int fd = ::open((dir / "run.xdmf.lock").c_str(), O_RDWR | O_CREAT, 0644);
  REQUIRE(fd >= 0);
  REQUIRE(::flock(fd, LOCK_EX) == 0);
  std::atomic<bool> done{false};
  std::thread writer([&] {
    out::write_xdmf(dir.string(), kGrid);
    done = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  CHECK_FALSE(done.load());  // it waits for the lock the test holds
  CHECK_FALSE(fs::exists(dir / "run.xdmf"));
  ::close(fd);  // releases the lock
  writer.join();
  CHECK(done.load());
  CHECK(grid_attributes(coflow::bench::slurp(dir / "run.xdmf"), "fluid").size() == 1);
  fs::remove_all(dir);
}

TEST_CASE("two writers of run.xdmf: each leaves a file holding its newest row", "[xdmf]") {
  const fs::path dir = fresh_dir("writers");
  constexpr int kRows = 200;
  std::atomic<int> stale{0};
  auto writer = [&](const std::string& component) {
    for (int i = 0; i < kRows; ++i) {
      out::append_index(dir.string(), component, {i, static_cast<double>(i), 1}, {"velocity"});
      out::write_xdmf(dir.string(), kGrid);
      // The row just indexed must be in the file: a later writer read the
      // indexes after this row went in.
      const std::string x = coflow::bench::slurp(dir / "run.xdmf");
      if (grid_attributes(x, component).size() < static_cast<std::size_t>(i + 1)) ++stale;
    }
  };
  std::thread a(writer, "fluid"), b(writer, "particles");
  a.join();
  b.join();
  CHECK(stale.load() == 0);
  const std::string x = coflow::bench::slurp(dir / "run.xdmf");
  CHECK(grid_attributes(x, "fluid").size() == kRows);
  CHECK(grid_attributes(x, "particles").size() == kRows);
  for (const auto& e : fs::directory_iterator(dir))
    CHECK(e.path().filename().string().find(".tmp.") == std::string::npos);  // no temporary left
  fs::remove_all(dir);
}
