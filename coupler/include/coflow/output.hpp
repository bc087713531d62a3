// The run directory shared by all components (layout: ARCHITECTURE.md,
// "Output"): parallel HDF5 snapshots, CSV series, the XDMF index, summary.json.
#pragma once

#include <mpi.h>

#include <array>
#include <cstdint>
#include <fstream>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "coflow/decomposition.hpp"

namespace coflow::output {

// A failed write of an output file (an HDF5 snapshot or checkpoint, a series
// row, a whole file): a component that fails with it adds the run
// directory's free space to its reason (run_component, low_space_note).
struct WriteError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Write a whole file under a temporary name, then rename it into place, so a
// reader never sees a half-written file.
void atomic_write(const std::string& path, const std::string& content);

// " (the file system holding DIR has N bytes free: ...)" where less than 64 MiB
// is free there, else "": appended to a failed write's message, so that a
// full disk is named (HDF5 and streams do not say why a write failed).
std::string low_space_note(const std::string& dir);

std::string snapshot_name(long step);  // "step_000042.h5"

// A CSV time series; only the process that creates it writes.
class Series {
 public:
  Series() = default;
  // A column's name and unit ("1" for a count or a ratio).
  struct Column {
    std::string name, unit;
  };
  // A new file starts with the header of names and a second line of units,
  // "# s,kg,...", which CSV readers skip as a comment (pandas comment='#',
  // numpy genfromtxt). append: continue an existing file (restart) instead.
  // A first column named "time" is written with 12 significant digits (3, not
  // 3.0000000000000027: a window's end accumulated in floating point); the
  // other columns with 17 (every bit).
  Series(const std::string& path, const std::vector<Column>& columns, bool append = false);
  void row(std::span<const double> values);
  bool is_open() const { return out_.is_open(); }

 private:
  std::ofstream out_;
  std::string path_;  // for a failed write's message
  std::size_t columns_ = 0;
  bool time_first_ = false;
};

// A field of the local array (block grown by `ghost`), `components` per cell.
struct GridField {
  std::string name;
  int components = 1;
  std::span<const double> data;
};

// Collective over `comm`: writes the owned part of each field into one HDF5
// file with datasets [nz][ny][nx] or [nz][ny][nx][c], and the attributes time
// and step. Written to a temporary name and renamed.
void write_grid(MPI_Comm comm, const std::string& path, double time, long step,
                const coupler::Index3& cells, const coupler::Box& owned, const coupler::Box& local,
                const std::vector<GridField>& fields);

struct PointField {
  std::string name;
  int components = 1;  // 1 or 3
  std::span<const double> data;
};

// Collective over `comm`: each rank contributes its `count` points. The file
// records `species_names` (species i is the i-th) and every dataset's units.
void write_points(MPI_Comm comm, const std::string& path, double time, long step, std::size_t count,
                  std::span<const std::int64_t> id, std::span<const std::int32_t> species,
                  const std::vector<PointField>& fields, const std::vector<std::string>& species_names = {});

// A table of rows (this rank's part): `columns` values per row, doubles or
// 64-bit integers (`integer`: the same on every rank), in `values` or
// `integers` (rows x columns).
struct Table {
  std::string name;
  int columns = 1;
  std::size_t rows = 0;
  bool integer = false;
  std::span<const double> values;
  std::span<const std::int64_t> integers;
};
// Collective over `comm`: one dataset [rows over all ranks][columns] per
// table, each rank's rows after those of the ranks below it (unstructured
// meshes: fv's adaptive grid writes its cells so).
void write_tables(MPI_Comm comm, const std::string& path, double time, long step,
                  const std::vector<Table>& tables);
// The first row of this rank's part of a table of `rows` local rows (the
// offset write_tables uses). Collective.
std::size_t first_row(MPI_Comm comm, std::size_t rows);

// Read back (serial) for restarts, tests and initial conditions.
// has_dataset: whether the HDF5 file at `path` holds a dataset `name` at its
// root (an optional field of an older checkpoint); throws when the file
// cannot be opened.
bool has_dataset(const std::string& path, const std::string& name);
std::vector<double> read_dataset(const std::string& path, const std::string& name,
                                 std::vector<std::size_t>* dims = nullptr);
// The shape of a dataset, and the block [start, start + count) of it (as
// many axes as the dataset has; row-major, the last axis fastest): a rank
// reads the part of a grid it owns, not the whole grid.
std::vector<std::size_t> dataset_shape(const std::string& path, const std::string& name);
std::vector<double> read_block(const std::string& path, const std::string& name,
                               const std::vector<std::size_t>& start, const std::vector<std::size_t>& count);
double read_time(const std::string& path);
// The "step" attribute of a file written by write_points or write_fields; -1 without one.
long read_step(const std::string& path);

// The snapshot index of one component, kept in <dir>/<component>/index.csv, and
// the ParaView index <dir>/run.xdmf rebuilt from every component's index.
struct SnapshotInfo {
  long number = 0;  // the file is <component>/step_<number>.h5
  double time = 0.0;
  std::size_t count = 0;  // points (particles); 0 for grids
};
void append_index(const std::string& dir, const std::string& component, const SnapshotInfo& info,
                  const std::vector<std::string>& fields);
// A component's index.csv: its snapshots, each with the fields its file holds
// (a restart may write other fields than the run before it).
struct IndexRow : SnapshotInfo {
  std::vector<std::string> fields;
};
struct IndexTable {
  std::vector<IndexRow> rows;
};
IndexTable read_index(const std::string& path);

struct GridGeometry {
  std::array<double, 3> lower{}, spacing{};
  std::array<long, 3> cells{};
};
// run.xdmf from the components' index.csv files. Each component's rank 0
// calls it after each snapshot: the read and the write are made under an
// exclusive lock on run.xdmf.lock, so that the last writer has read every
// index row written before it (without it a writer that read the indexes
// before another's row went in could rename its file over the other's).
void write_xdmf(const std::string& dir, const GridGeometry& grid);

// JSON string literal with escapes.
std::string json_quote(const std::string& s);

}  // namespace coflow::output
