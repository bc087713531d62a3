#include "fluid/fv/amr/composite_output.hpp"

#include <fmt/format.h>

#include <span>
#include <sstream>
#include <stdexcept>

#include "coflow/output.hpp"

namespace coflow::fluid::fv::amr {
namespace {

// One level's local cells as an unstructured mesh: corners (x, y, z per
// node, own corners per cell), connectivity (global node ids) and fields.
struct LevelMesh {
  std::vector<double> nodes;
  std::vector<std::int64_t> cells;
  std::vector<std::vector<double>> fields;  // per CompositeField, rows x columns
  std::size_t count = 0;
};

int columns(const CompositeField& f) {
  return f.components == 2 ? 3 : f.components;
}

// Local cell c's component q of field f (data: c's patch, base: c's first value in it).
double value(const CompositeField& f, std::span<const double> data, std::size_t base, long c, int q) {
  if (!f.values.empty()) return f.values.at(static_cast<std::size_t>(c * f.components + q));
  return f.scale * data[base + static_cast<std::size_t>(f.first + q)];
}

LevelMesh level_mesh(const CompositeGrid& g, int level, const std::vector<CompositeField>& fields) {
  // Corner offsets in VTK order: the bottom face counter-clockwise, then the top.
  static const int corner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                   {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const int corners = g.dims() == 3 ? 8 : 4;
  const auto& forest = g.forest();
  const auto nc = static_cast<std::size_t>(forest.spec().components);
  LevelMesh m;
  m.fields.resize(fields.size());
  for (long c = 0; c < g.local_cells(); ++c) {
    const auto cell = g.local_cell(c);
    if (cell.level != level) continue;
    const double h = g.spacing(level);
    const auto x = g.centre(cell);
    for (int k = 0; k < corners; ++k)
      for (int d = 0; d < 3; ++d)
        m.nodes.push_back(x[static_cast<std::size_t>(d)] + (d < g.dims() ? (corner[k][d] - 0.5) * h : 0.0));
    const auto data = forest.data(static_cast<std::size_t>(c / g.cells_per_patch()));
    const std::size_t base = static_cast<std::size_t>(c % g.cells_per_patch()) * nc;
    for (std::size_t f = 0; f < fields.size(); ++f)
      for (int q = 0; q < columns(fields[f]); ++q)
        m.fields[f].push_back(q < fields[f].components ? value(fields[f], data, base, c, q) : 0.0);
    ++m.count;
  }
  // Node ids: this rank's nodes follow the lower ranks' (write_tables' order).
  const auto first = static_cast<std::int64_t>(output::first_row(forest.comm(), m.count * corners));
  for (std::size_t i = 0; i < m.count * static_cast<std::size_t>(corners); ++i)
    m.cells.push_back(first + static_cast<std::int64_t>(i));
  return m;
}

void write_xmf(const std::string& path, const std::string& h5, int dims, double time,
               const std::vector<unsigned long long>& counts, const std::vector<CompositeField>& fields) {
  const int corners = dims == 3 ? 8 : 4;
  std::ostringstream x;
  x << "<?xml version=\"1.0\"?>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
    << "<Grid Name=\"fluid (adaptive)\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
    << fmt::format("<Time Value=\"{:.12g}\"/>\n", time);  // as run.xdmf and index.csv
  auto item = [&](const std::string& name, unsigned long long rows, int cols, bool integer) {
    return fmt::format(
        "<DataItem Dimensions=\"{} {}\" NumberType=\"{}\" Precision=\"8\" Format=\"HDF\">{}:/{}</DataItem>\n",
        rows, cols, integer ? "Int" : "Float", h5, name);
  };
  for (std::size_t l = 0; l < counts.size(); ++l) {
    if (counts[l] == 0) continue;
    const std::string p = fmt::format("level{}_", l);
    x << fmt::format("<Grid Name=\"level {}\" GridType=\"Uniform\">\n", l)
      << fmt::format("<Topology TopologyType=\"{}\" NumberOfElements=\"{}\">\n",
                     dims == 3 ? "Hexahedron" : "Quadrilateral", counts[l])
      << item(p + "cells", counts[l], corners, true) << "</Topology>\n<Geometry GeometryType=\"XYZ\">\n"
      << item(p + "nodes", counts[l] * corners, 3, false) << "</Geometry>\n";
    for (const auto& f : fields)
      x << fmt::format("<Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"Cell\">\n", f.name,
                       columns(f) == 3 ? "Vector" : "Scalar")
        << item(p + f.name, counts[l], columns(f), false) << "</Attribute>\n";
    x << "<Attribute Name=\"level\" AttributeType=\"Scalar\" Center=\"Cell\">\n"
      << item(p + "level", counts[l], 1, false) << "</Attribute>\n</Grid>\n";
  }
  x << "</Grid>\n</Domain>\n</Xdmf>\n";
  output::atomic_write(path, x.str());  // whole or not at all, its errors checked
}

}  // namespace

void write_composite(const CompositeGrid& g, const std::string& dir, const std::string& stem, double time,
                     long step, const std::vector<CompositeField>& fields) {
  const auto& forest = g.forest();
  const int corners = g.dims() == 3 ? 8 : 4;
  std::vector<LevelMesh> meshes;
  std::vector<std::vector<double>> levels;
  std::vector<output::Table> tables;
  std::vector<unsigned long long> counts;
  for (int l = 0; l <= forest.spec().max_level; ++l) meshes.push_back(level_mesh(g, l, fields));
  levels.resize(meshes.size());
  for (std::size_t l = 0; l < meshes.size(); ++l) {
    const auto& m = meshes[l];
    const std::string p = fmt::format("level{}_", l);
    levels[l].assign(m.count, static_cast<double>(l));
    tables.push_back({p + "nodes", 3, m.count * corners, false, m.nodes, {}});
    tables.push_back({p + "cells", corners, m.count, true, {}, m.cells});
    for (std::size_t f = 0; f < fields.size(); ++f)
      tables.push_back({p + fields[f].name, columns(fields[f]), m.count, false, m.fields[f], {}});
    tables.push_back({p + "level", 1, m.count, false, levels[l], {}});
    unsigned long long n = m.count, total = 0;
    MPI_Allreduce(&n, &total, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, forest.comm());
    counts.push_back(total);
  }
  output::write_tables(forest.comm(), dir + "/" + stem + ".h5", time, step, tables);
  int rank = 0;
  MPI_Comm_rank(forest.comm(), &rank);
  if (rank == 0) write_xmf(dir + "/" + stem + ".xmf", stem + ".h5", g.dims(), time, counts, fields);
}

}  // namespace coflow::fluid::fv::amr
