#include "fluid/grid/cell_fields.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "coflow/output.hpp"

namespace coflow::fluid::grid {

void save_cell_fields(MPI_Comm comm, const std::string& path, double time, long step, const coupler::Index3& cells,
                      const coupler::Box& owned, const std::vector<output::GridField>& fields) {
  output::write_grid(comm, path, time, step, cells, owned, owned, fields);
}

namespace {

// Names the first owned value of `name` that is not finite (out: the owned
// block, x fastest, `components` per cell).
[[noreturn]] void refuse_not_finite(const std::string& path, const std::string& name,
                                    const coupler::Box& owned, int components,
                                    const std::vector<double>& out) {
  std::size_t n = 0;
  while (n < out.size() && std::isfinite(out[n])) ++n;
  const auto C = static_cast<std::size_t>(components), cell = n / C;
  const auto nx = static_cast<std::size_t>(owned.extent(0)), ny = static_cast<std::size_t>(owned.extent(1));
  const long i = owned.lo[0] + static_cast<long>(cell % nx),
             j = owned.lo[1] + static_cast<long>(cell / nx % ny),
             k = owned.lo[2] + static_cast<long>(cell / (nx * ny));
  throw std::runtime_error(fmt::format(
      "{}: '{}' holds a value that is not finite ({}) at cell ({}, {}, {}){}: the checkpoint is damaged; "
      "restart from another one (run.checkpoint.keep sets how many a run keeps)",
      path, name, n < out.size() ? out[n] : 0.0, i, j, k, C > 1 ? fmt::format(", component {}", n % C) : ""));
}

}  // namespace

std::vector<double> load_cell_field(const std::string& path, const std::string& name, const coupler::Index3& cells,
                                    const coupler::Box& owned, int components) {
  const std::vector<std::size_t> dims = output::dataset_shape(path, name);
  const bool scalar = components == 1 && dims.size() == 3;
  const bool same = (scalar || (dims.size() == 4 && dims[3] == std::size_t(components))) &&
                    dims[0] == std::size_t(cells[2]) && dims[1] == std::size_t(cells[1]) &&
                    dims[2] == std::size_t(cells[0]);
  if (!same)
    throw std::runtime_error(fmt::format("{}: '{}' is for another grid or another number of components (this run: "
                                         "{}x{}x{} cells, {} per cell): restart with the configuration that wrote it",
                                         path, name, cells[0], cells[1], cells[2], components));
  // This rank's block only ([z][y][x][component], x fastest: the order of out).
  auto at = [&owned](int a) { return static_cast<std::size_t>(owned.lo[a]); };
  auto n = [&owned](int a) { return static_cast<std::size_t>(owned.extent(a)); };
  std::vector<std::size_t> start{at(2), at(1), at(0)}, count{n(2), n(1), n(0)};
  if (!scalar) start.push_back(0), count.push_back(static_cast<std::size_t>(components));
  const std::vector<double> out = output::read_block(path, name, start, count);
  double sum = 0.0;  // 0 x value: 0, or NaN where a value is not finite
  for (const double v : out) sum += 0.0 * v;
  if (sum != 0.0) refuse_not_finite(path, name, owned, components, out);
  return out;
}

void save_text(MPI_Comm comm, const std::string& path, const std::string& text) {
  int rank = 0, written = 1;
  MPI_Comm_rank(comm, &rank);
  if (rank == 0) {
    try {  // closed before it is judged: a full disk shows at the close
      output::atomic_write(path, text);
    } catch (const std::exception&) {
      written = 0;
    }
  }
  MPI_Bcast(&written, 1, MPI_INT, 0, comm);
  if (!written) throw output::WriteError(fmt::format("cannot write {}", path));
}

void save_number(MPI_Comm comm, const std::string& path, double value) {
  save_text(comm, path, fmt::format("{:a}\n", value));
}

double load_number(const std::string& path, double absent) {
  if (!std::filesystem::exists(path)) return absent;
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.pop_back();
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v) || v < 0.0)
    throw std::runtime_error(fmt::format(
        "{}: holds '{}', not a finite number of zero or more (a damaged checkpoint)", path, text));
  return v;
}

}  // namespace coflow::fluid::grid
