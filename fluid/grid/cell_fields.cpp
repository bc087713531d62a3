#include "fluid/grid/cell_fields.hpp"

#include <stdexcept>

#include <fmt/format.h>

namespace coflow::fluid::grid {

void save_cell_fields(MPI_Comm comm, const std::string& path, double time, long step, const coupler::Index3& cells,
                      const coupler::Box& owned, const std::vector<output::GridField>& fields) {
  output::write_grid(comm, path, time, step, cells, owned, owned, fields);
}

std::vector<double> load_cell_field(const std::string& path, const std::string& name, const coupler::Index3& cells,
                                    const coupler::Box& owned, int components) {
  std::vector<std::size_t> dims;
  const std::vector<double> all = output::read_dataset(path, name, &dims);
  const bool scalar = components == 1 && dims.size() == 3;
  const bool same = (scalar || (dims.size() == 4 && dims[3] == std::size_t(components))) &&
                    dims[0] == std::size_t(cells[2]) && dims[1] == std::size_t(cells[1]) &&
                    dims[2] == std::size_t(cells[0]);
  if (!same)
    throw std::runtime_error(fmt::format("{}: '{}' is for another grid or another number of components (this run: "
                                         "{}x{}x{} cells, {} per cell): restart with the configuration that wrote it",
                                         path, name, cells[0], cells[1], cells[2], components));
  const long C = components;
  std::vector<double> out;
  out.reserve(static_cast<std::size_t>(owned.volume() * C));
  for (long k = owned.lo[2]; k < owned.hi[2]; ++k)
    for (long j = owned.lo[1]; j < owned.hi[1]; ++j)
      for (long i = owned.lo[0]; i < owned.hi[0]; ++i)
        for (long q = 0; q < C; ++q) out.push_back(all[static_cast<std::size_t>(((k * cells[1] + j) * cells[0] + i) * C + q)]);
  return out;
}

}  // namespace coflow::fluid::grid
