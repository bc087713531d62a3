#include "coflow/output.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <hdf5.h>
#include <sys/file.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "coflow/config.hpp"

namespace coflow::output {

namespace fs = std::filesystem;

void atomic_write(const std::string& path, const std::string& content) {
  // The host, process and thread in the name: two writers never share a
  // temporary (process ids repeat across the nodes of a cluster).
  char host[256] = "host";
  ::gethostname(host, sizeof host - 1);
  host[sizeof host - 1] = '\0';
  const std::string tmp = fmt::format("{}.tmp.{}.{}.{}", path, host, ::getpid(), ::gettid());
  // A failed write leaves no temporary behind (a full disk kept an empty
  // summary.json.tmp.* beside the run's files).
  const auto give_up = [&](const std::string& what) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw WriteError(what);
  };
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) give_up(fmt::format("cannot write '{}'", tmp));
    out << content;
    out.close();  // where a network file system reports its write errors
    if (!out) give_up(fmt::format("failed writing '{}'", tmp));
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) give_up(fmt::format("cannot rename '{}' to '{}': {}", tmp, path, ec.message()));
}

std::string low_space_note(const std::string& dir) {
  struct statvfs v {};
  if (::statvfs(dir.empty() ? "." : dir.c_str(), &v) != 0) return "";
  const double free_bytes = static_cast<double>(v.f_bavail) * static_cast<double>(v.f_frsize);
  if (free_bytes >= 64.0 * 1024 * 1024) return "";
  return fmt::format(
      " (the file system holding {} has {:.0f} bytes free: the disk is full or nearly; free space or set "
      "run.output.dir elsewhere; a run with a checkpoint goes on from it with --restart latest)",
      dir, free_bytes);
}

std::string snapshot_name(long step) { return fmt::format("step_{:06d}.h5", step); }

Series::Series(const std::string& path, const std::vector<Column>& columns, bool append)
    : path_(path), columns_(columns.size()), time_first_(!columns.empty() && columns[0].name == "time") {
  std::string header;
  for (std::size_t i = 0; i < columns.size(); ++i) header += (i ? "," : "") + columns[i].name;
  if (append && fs::exists(path)) {
    // A restart appends to the series of the run it goes on from: the rows
    // must be that file's columns (other probes, pressure drops or walls
    // would put values under other names).
    std::ifstream in(path);
    std::string first;
    std::getline(in, first);
    if (first != header)
      throw std::runtime_error(fmt::format(
          "{}: the run this restart goes on from wrote the columns {}; this run writes {}. A restart into "
          "its directory appends rows, so it keeps the output settings (run.output.probes, pressure_drops, "
          "the walls) of that run. The directory is cut back to the checkpoint, which is still there: "
          "restart again with that run's settings, or into a new run.output.dir",
          path, first, header));
    out_.open(path, std::ios::app);
    if (!out_) throw std::runtime_error(fmt::format("cannot append to '{}'", path));
    return;
  }
  out_.open(path, std::ios::trunc);
  if (!out_) throw std::runtime_error(fmt::format("cannot write '{}'", path));
  out_ << header << "\n# ";
  for (std::size_t i = 0; i < columns.size(); ++i) out_ << (i ? "," : "") << columns[i].unit;
  out_ << '\n';
  out_.flush();
}

void Series::row(std::span<const double> values) {
  if (!out_.is_open()) return;
  if (values.size() != columns_) throw std::logic_error("series row with the wrong number of values");
  std::string line;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i) line += ',';
    line += i == 0 && time_first_ ? fmt::format("{:.12g}", values[i]) : fmt::format("{:.17g}", values[i]);
  }
  out_ << line << '\n';
  out_.flush();
  if (!out_) throw WriteError(fmt::format("cannot append a row to '{}'", path_));
}

namespace {

// The length of the well-formed UTF-8 sequence at s[i] (RFC 3629: no overlong
// forms, no surrogates, nothing above U+10FFFF), or 0 where there is none.
std::size_t utf8_length(const std::string& s, std::size_t i) {
  const auto b = [&](std::size_t k) { return static_cast<unsigned char>(s[i + k]); };
  const auto cont = [&](std::size_t k) { return i + k < s.size() && (b(k) & 0xC0) == 0x80; };
  const unsigned char c = b(0);
  if (c < 0x80) return 1;
  if (c >= 0xC2 && c <= 0xDF) return cont(1) ? 2 : 0;
  if (c >= 0xE0 && c <= 0xEF) {
    if (!cont(1) || !cont(2)) return 0;
    if ((c == 0xE0 && b(1) < 0xA0) || (c == 0xED && b(1) > 0x9F)) return 0;  // overlong; surrogate
    return 3;
  }
  if (c >= 0xF0 && c <= 0xF4) {
    if (!cont(1) || !cont(2) || !cont(3)) return 0;
    if ((c == 0xF0 && b(1) < 0x90) || (c == 0xF4 && b(1) > 0x8F)) return 0;  // overlong; past U+10FFFF
    return 4;
  }
  return 0;
}

}  // namespace

// JSON text must be UTF-8 (RFC 8259 §8.1): a byte that starts no well-formed
// sequence (a Latin-1 path in a failure reason) becomes U+FFFD, so that every
// JSON reader still reads the file.
std::string json_quote(const std::string& s) {
  std::string o = "\"";
  for (std::size_t i = 0; i < s.size();) {
    const char c = s[i];
    const std::size_t n = utf8_length(s, i);
    if (n == 0) {
      o += "\\ufffd";
      ++i;
      continue;
    }
    switch (c) {
      case '"': o += "\\\""; break;
      case '\\': o += "\\\\"; break;
      case '\n': o += "\\n"; break;
      case '\t': o += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20)
          o += fmt::format("\\u{:04x}", static_cast<int>(c));
        else
          o.append(s, i, n);
    }
    i += n;
  }
  return o + "\"";
}

// ------------------------------------------------------------------ HDF5 ---

namespace {

// A failed HDF5 call: a WriteError unless it was reading (read_dataset,
// read_block: "reading", "selecting"), so that a component's failure names
// the run directory's free space only after a failed write.
[[noreturn]] void h5fail(const char* what) {
  const std::string m = fmt::format("HDF5 error while {}", what);
  if (std::string_view(what).starts_with("reading") || std::string_view(what) == "selecting")
    throw std::runtime_error(m);
  throw WriteError(m);
}

void h5check(herr_t e, const char* what) {
  if (e < 0) h5fail(what);
}

hid_t check_id(hid_t id, const char* what) {
  if (id < 0) h5fail(what);
  return id;
}

hid_t create_parallel(MPI_Comm comm, const std::string& path) {
  hid_t fapl = check_id(H5Pcreate(H5P_FILE_ACCESS), "creating a property list");
  h5check(H5Pset_fapl_mpio(fapl, comm, MPI_INFO_NULL), "selecting MPI-IO");
  hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
  H5Pclose(fapl);
  return check_id(f, ("creating " + path).c_str());
}

void write_scalar_attr(hid_t obj, const char* name, double v) {
  hid_t s = H5Screate(H5S_SCALAR);
  hid_t a = H5Acreate2(obj, name, H5T_NATIVE_DOUBLE, s, H5P_DEFAULT, H5P_DEFAULT);
  h5check(H5Awrite(a, H5T_NATIVE_DOUBLE, &v), "writing an attribute");
  H5Aclose(a);
  H5Sclose(s);
}

void write_long_attr(hid_t obj, const char* name, long v) {
  hid_t s = H5Screate(H5S_SCALAR);
  hid_t a = H5Acreate2(obj, name, H5T_NATIVE_LONG, s, H5P_DEFAULT, H5P_DEFAULT);
  h5check(H5Awrite(a, H5T_NATIVE_LONG, &v), "writing an attribute");
  H5Aclose(a);
  H5Sclose(s);
}

void write_string_attr(hid_t obj, const char* name, const std::string& v) {
  if (v.empty()) return;
  hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, v.size());
  H5Tset_strpad(t, H5T_STR_NULLPAD);
  hid_t s = H5Screate(H5S_SCALAR);
  hid_t a = H5Acreate2(obj, name, t, s, H5P_DEFAULT, H5P_DEFAULT);
  h5check(H5Awrite(a, t, v.data()), "writing an attribute");
  H5Aclose(a);
  H5Sclose(s);
  H5Tclose(t);
}

// The SI units of the datasets coflow writes (docs/output.md), an attribute
// "units" of each; "" for a name it does not know.
std::string units_of(const std::string& name) {
  static const std::map<std::string, std::string> u{{"velocity", "m/s"},
                                                    {"pressure", "Pa"},
                                                    {"kinematic_pressure", "m^2/s^2"},
                                                    {"density", "kg/m^3"},
                                                    {"solid_fraction", "1"},
                                                    {"vorticity", "1/s"},
                                                    {"k", "m^2/s^2"},
                                                    {"epsilon", "m^2/s^3"},
                                                    {"momentum_source", "N/m^3"},
                                                    {"position", "m"},
                                                    {"angular_velocity", "rad/s"},
                                                    {"radius", "m"},
                                                    {"force", "N"},
                                                    {"id", "1"},
                                                    {"species", "1"},
                                                    {"populations", "lattice units"},
                                                    {"phase", "1"},
                                                    {"nu_t", "m^2/s"},
                                                    {"y_plus", "1"},
                                                    {"divergence", "1/s"},
                                                    {"solid_velocity", "m/s"},
                                                    {"mass", "kg"},
                                                    {"inertia", "kg m^2"},
                                                    {"diameter", "m"},
                                                    {"torque", "N m"},
                                                    {"hydrodynamic_force", "N"},
                                                    {"hydrodynamic_torque", "N m"},
                                                    {"nodes", "m"},
                                                    {"cells", "1"},
                                                    {"level", "1"}};
  // The adaptive grid's datasets are named per level: level<L>_<name>.
  std::string base = name;
  if (const auto digits = name.find_first_not_of("0123456789", 5);
      name.starts_with("level") && digits > 5 && digits != std::string::npos && name[digits] == '_')
    base = name.substr(digits + 1);
  const auto it = u.find(base);
  return it == u.end() ? "" : it->second;
}

// Write `local` (this rank's part, starting at `offset`) into a new dataset.
void write_block(hid_t file, const std::string& name, hid_t type, const std::vector<hsize_t>& global,
                 const std::vector<hsize_t>& offset, const std::vector<hsize_t>& count,
                 const void* local) {
  const int rank = static_cast<int>(global.size());
  hid_t fs_ = H5Screate_simple(rank, global.data(), nullptr);
  hid_t ds = check_id(H5Dcreate2(file, name.c_str(), type, fs_, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                      ("creating dataset " + name).c_str());
  write_string_attr(ds, "units", units_of(name));
  hsize_t n = 1;
  for (auto c : count) n *= c;
  hid_t ms = H5Screate_simple(rank, count.data(), nullptr);
  if (n == 0) {
    H5Sselect_none(fs_);
    H5Sselect_none(ms);
  } else {
    h5check(H5Sselect_hyperslab(fs_, H5S_SELECT_SET, offset.data(), nullptr, count.data(), nullptr),
            "selecting a hyperslab");
  }
  hsize_t total = 1;
  for (auto g : global) total *= g;
  // An empty dataset has no storage: HDF5 1.10 fails a collective write to it,
  // and every rank knows the global size, so all skip the write together.
  if (total > 0) {
    hid_t xfer = H5Pcreate(H5P_DATASET_XFER);
    H5Pset_dxpl_mpio(xfer, H5FD_MPIO_COLLECTIVE);
    static const double nothing = 0.0;  // HDF5 wants a buffer even for an empty selection
    h5check(H5Dwrite(ds, type, ms, fs_, xfer, local ? local : &nothing), ("writing dataset " + name).c_str());
    H5Pclose(xfer);
  }
  H5Sclose(ms);
  H5Dclose(ds);
  H5Sclose(fs_);
}

void finish_file(MPI_Comm comm, hid_t f, const std::string& tmp, const std::string& path) {
  h5check(H5Fclose(f), "closing a file");
  MPI_Barrier(comm);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (rank == 0) fs::rename(tmp, path);
}

// A new snapshot file (collective) at the temporary name, with its time and step.
hid_t create_snapshot(MPI_Comm comm, const std::string& tmp, double time, long step) {
  hid_t f = create_parallel(comm, tmp);
  write_scalar_attr(f, "time", time);
  write_long_attr(f, "step", step);
  write_string_attr(f, "time_units", "s");
  return f;
}

// A snapshot's temporary, removed unless finish_file renamed it: a write that
// failed (a full disk) leaves no step_N.h5.tmp behind.
struct Temporary {
  std::string path;
  bool renamed = false;
  ~Temporary() {
    std::error_code ec;
    if (!renamed) fs::remove(path, ec);
  }
};

std::string tmp_name(MPI_Comm comm, const std::string& path) {
  // Same name on every rank of the collective.
  return path + ".tmp";
}

}  // namespace

void write_grid(MPI_Comm comm, const std::string& path, double time, long step,
                const coupler::Index3& cells, const coupler::Box& owned, const coupler::Box& local,
                const std::vector<GridField>& fields) {
  const std::string tmp = tmp_name(comm, path);
  Temporary guard{tmp};
  hid_t f = create_snapshot(comm, tmp, time, step);
  write_string_attr(f, "layout", "[nz][ny][nx] or [nz][ny][nx][component], x fastest; cell centres");
  const long nx = owned.extent(0), ny = owned.extent(1), nz = owned.extent(2);
  const long lx = local.extent(0), ly = local.extent(1);
  std::vector<double> buf;
  for (const auto& fld : fields) {
    const int nc = fld.components;
    buf.resize(static_cast<std::size_t>(nx * ny * nz * nc));
    std::size_t o = 0;
    for (long k = owned.lo[2]; k < owned.hi[2]; ++k)
      for (long j = owned.lo[1]; j < owned.hi[1]; ++j)
        for (long i = owned.lo[0]; i < owned.hi[0]; ++i) {
          const long li = ((k - local.lo[2]) * ly + (j - local.lo[1])) * lx + (i - local.lo[0]);
          for (int c = 0; c < nc; ++c) buf[o++] = fld.data[li * nc + c];
        }
    std::vector<hsize_t> g{hsize_t(cells[2]), hsize_t(cells[1]), hsize_t(cells[0])};
    std::vector<hsize_t> off{hsize_t(owned.lo[2]), hsize_t(owned.lo[1]), hsize_t(owned.lo[0])};
    std::vector<hsize_t> cnt{hsize_t(nz), hsize_t(ny), hsize_t(nx)};
    if (nc > 1) {
      g.push_back(nc);
      off.push_back(0);
      cnt.push_back(nc);
    }
    write_block(f, fld.name, H5T_NATIVE_DOUBLE, g, off, cnt, buf.data());
  }
  finish_file(comm, f, tmp, path);
  guard.renamed = true;
}

void write_points(MPI_Comm comm, const std::string& path, double time, long step, std::size_t count,
                  std::span<const std::int64_t> id, std::span<const std::int32_t> species,
                  const std::vector<PointField>& fields, const std::vector<std::string>& species_names) {
  unsigned long long n = count, total = 0;
  const unsigned long long offset = first_row(comm, count);
  MPI_Allreduce(&n, &total, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm);
  const std::string tmp = tmp_name(comm, path);
  Temporary guard{tmp};
  hid_t f = create_snapshot(comm, tmp, time, step);
  write_block(f, "id", H5T_NATIVE_INT64, {total}, {offset}, {n}, id.data());
  write_block(f, "species", H5T_NATIVE_INT32, {total}, {offset}, {n}, species.data());
  // The species table: index i of "species" is the i-th name (comma-separated).
  write_string_attr(f, "species_names", fmt::format("{}", fmt::join(species_names, ",")));
  for (const auto& fld : fields) {
    std::vector<hsize_t> g{total}, off{offset}, cnt{n};
    if (fld.components > 1) {
      g.push_back(fld.components);
      off.push_back(0);
      cnt.push_back(fld.components);
    }
    write_block(f, fld.name, H5T_NATIVE_DOUBLE, g, off, cnt, fld.data.data());
  }
  finish_file(comm, f, tmp, path);
  guard.renamed = true;
}

std::size_t first_row(MPI_Comm comm, std::size_t rows) {
  unsigned long long n = rows, offset = 0;
  MPI_Exscan(&n, &offset, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  return rank == 0 ? 0 : static_cast<std::size_t>(offset);
}

void write_tables(MPI_Comm comm, const std::string& path, double time, long step,
                  const std::vector<Table>& tables) {
  const std::string tmp = tmp_name(comm, path);
  Temporary guard{tmp};
  hid_t f = create_snapshot(comm, tmp, time, step);
  for (const auto& t : tables) {
    const std::size_t given = t.integer ? t.integers.size() : t.values.size();
    if (given != t.rows * static_cast<std::size_t>(t.columns))
      throw std::logic_error(fmt::format("table {}: {} values for {} rows of {}", t.name, given, t.rows, t.columns));
    unsigned long long n = t.rows, total = 0;
    MPI_Allreduce(&n, &total, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm);
    const hsize_t offset = first_row(comm, t.rows), columns = static_cast<hsize_t>(t.columns);
    write_block(
        f, t.name, t.integer ? H5T_NATIVE_INT64 : H5T_NATIVE_DOUBLE, {total, columns}, {offset, 0},
        {n, columns},
        t.integer ? static_cast<const void*>(t.integers.data()) : static_cast<const void*>(t.values.data()));
  }
  finish_file(comm, f, tmp, path);
  guard.renamed = true;
}

// Opens an existing HDF5 file read-only, with HDF5's own error stack kept off
// stderr (a missing or foreign file is reported once, by the caller's message).
static hid_t open_for_reading(const std::string& path) {
  if (const std::string why = config::file_problem(path); !why.empty())
    throw std::runtime_error(fmt::format("cannot open HDF5 file '{}': {}", path, why));
  H5E_auto2_t func = nullptr;
  void* data = nullptr;
  H5Eget_auto2(H5E_DEFAULT, &func, &data);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  H5Eset_auto2(H5E_DEFAULT, func, data);
  if (f < 0)
    throw std::runtime_error(fmt::format(
        "cannot open HDF5 file '{}': not an HDF5 file, truncated, or locked by a process writing it", path));
  return f;
}

bool has_dataset(const std::string& path, const std::string& name) {
  hid_t f = open_for_reading(path);
  const bool found = H5Lexists(f, name.c_str(), H5P_DEFAULT) > 0;
  H5Fclose(f);
  return found;
}

namespace {

// An open dataset (closed with its file).
struct OpenDataset {
  hid_t file = -1, set = -1, space = -1;
  OpenDataset(const std::string& path, const std::string& name) {
    file = open_for_reading(path);
    set = H5Lexists(file, name.c_str(), H5P_DEFAULT) > 0 ? H5Dopen2(file, name.c_str(), H5P_DEFAULT) : -1;
    if (set < 0) {
      H5Fclose(file);
      throw std::runtime_error(fmt::format("'{}' has no dataset '{}'", path, name));
    }
    space = H5Dget_space(set);
  }
  ~OpenDataset() {
    H5Sclose(space);
    H5Dclose(set);
    H5Fclose(file);
  }
  OpenDataset(const OpenDataset&) = delete;
  OpenDataset& operator=(const OpenDataset&) = delete;
  std::vector<hsize_t> shape() const {
    std::vector<hsize_t> d(static_cast<std::size_t>(std::max(0, H5Sget_simple_extent_ndims(space))));
    H5Sget_simple_extent_dims(space, d.data(), nullptr);
    return d;
  }
};

}  // namespace

std::vector<double> read_dataset(const std::string& path, const std::string& name,
                                 std::vector<std::size_t>* dims) {
  OpenDataset ds(path, name);
  const auto d = ds.shape();
  std::size_t n = 1;
  for (auto x : d) n *= x;
  std::vector<double> out(n);
  if (n) h5check(H5Dread(ds.set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()), "reading");
  if (dims) dims->assign(d.begin(), d.end());
  return out;
}

std::vector<std::size_t> dataset_shape(const std::string& path, const std::string& name) {
  const auto d = OpenDataset(path, name).shape();
  return {d.begin(), d.end()};
}

std::vector<double> read_block(const std::string& path, const std::string& name,
                               const std::vector<std::size_t>& start, const std::vector<std::size_t>& count) {
  OpenDataset ds(path, name);
  const auto shape = ds.shape();
  if (start.size() != shape.size() || count.size() != shape.size())
    throw std::logic_error(fmt::format("{}: a block of '{}' with another number of axes", path, name));
  std::size_t n = 1;
  for (std::size_t a = 0; a < shape.size(); ++a) {
    if (start[a] + count[a] > shape[a])
      throw std::logic_error(fmt::format("{}: a block beyond the end of '{}'", path, name));
    n *= count[a];
  }
  std::vector<double> out(n);
  if (n == 0) return out;
  const std::vector<hsize_t> s(start.begin(), start.end()), c(count.begin(), count.end());
  h5check(H5Sselect_hyperslab(ds.space, H5S_SELECT_SET, s.data(), nullptr, c.data(), nullptr), "selecting");
  const hid_t mem = H5Screate_simple(static_cast<int>(c.size()), c.data(), nullptr);
  const herr_t read = H5Dread(ds.set, H5T_NATIVE_DOUBLE, mem, ds.space, H5P_DEFAULT, out.data());
  H5Sclose(mem);
  h5check(read, "reading");
  return out;
}

long read_step(const std::string& path) {
  hid_t f = open_for_reading(path);
  long step = -1;
  if (H5Aexists(f, "step") > 0) {
    hid_t a = H5Aopen(f, "step", H5P_DEFAULT);
    H5Aread(a, H5T_NATIVE_LONG, &step);
    H5Aclose(a);
  }
  H5Fclose(f);
  return step;
}

double read_time(const std::string& path) {
  hid_t f = open_for_reading(path);
  double t = 0;
  hid_t a = H5Aexists(f, "time") > 0 ? H5Aopen(f, "time", H5P_DEFAULT) : -1;
  if (a >= 0) {
    H5Aread(a, H5T_NATIVE_DOUBLE, &t);
    H5Aclose(a);
  }
  H5Fclose(f);
  return t;
}

// ------------------------------------------------------------------ XDMF ---

void append_index(const std::string& dir, const std::string& component, const SnapshotInfo& info,
                  const std::vector<std::string>& fields) {
  const std::string path = fmt::format("{}/{}/index.csv", dir, component);
  std::string text;
  {
    std::ifstream in(path);
    if (in) {
      std::stringstream ss;
      ss << in.rdbuf();
      text = ss.str();
    }
  }
  if (text.empty()) text = "snapshot,time,count,fields\n";
  // The time to 12 significant digits: the rest is the round-off of adding
  // windows (0.1, not 0.099999999999999992).
  text += fmt::format("{},{:.12g},{},{}\n", info.number, info.time, info.count, fmt::join(fields, " "));
  atomic_write(path, text);
}

IndexTable read_index(const std::string& path) {
  IndexTable t;
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line)) return t;  // the header: snapshot,time,count,fields
  while (std::getline(in, line)) {
    IndexRow s;
    if (std::sscanf(line.c_str(), "%ld,%lf,%zu", &s.number, &s.time, &s.count) != 3) continue;
    std::size_t at = 0;
    for (int commas = 0; commas < 3 && at != std::string::npos; ++commas) at = line.find(',', at == 0 ? 0 : at + 1);
    if (at != std::string::npos) {
      std::stringstream fs(line.substr(at + 1));
      std::string f;
      while (fs >> f) s.fields.push_back(f);
    }
    t.rows.push_back(std::move(s));
  }
  return t;
}

namespace {

// An exclusive lock on a file next to run.xdmf, held while the object lives
// (flock: released when the descriptor closes, also when the process dies).
// Where the file system has no locks (Lustre mounted noflock, NFS nolock:
// ENOSYS, ENOLCK, ...) it goes on without one: the lock only keeps run.xdmf
// fresh between two writers, and the last write of the run has every row.
class FileLock {
 public:
  explicit FileLock(const std::string& path) : fd_(::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644)) {
    while (fd_ >= 0 && ::flock(fd_, LOCK_EX) != 0 && errno == EINTR) {
    }
  }
  ~FileLock() {
    if (fd_ >= 0) ::close(fd_);
  }
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_;
};

bool is_vector_field(const std::string& f) {
  return f == "velocity" || f == "vorticity" || f == "momentum_source" || f == "solid_velocity";
}

void add_fluid_grids(std::string& x, const IndexTable& fluid, const GridGeometry& grid) {
  const long nx = grid.cells[0], ny = grid.cells[1], nz = grid.cells[2];
  x += "  <Grid Name=\"fluid\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const auto& s : fluid.rows) {
    const std::string file = "fluid/" + snapshot_name(s.number);
    x +=
        fmt::format("   <Grid Name=\"fluid\" GridType=\"Uniform\">\n    <Time Value=\"{:.12g}\"/>\n", s.time);
    x += fmt::format("    <Topology TopologyType=\"3DCoRectMesh\" Dimensions=\"{} {} {}\"/>\n", nz + 1,
                     ny + 1, nx + 1);
    x += "    <Geometry GeometryType=\"ORIGIN_DXDYDZ\">\n";
    // Eight-byte numbers: XDMF reads four unless told (an origin of 100 m
    // with 0.1 mm cells would be off by a tenth of a cell).
    x += fmt::format(
        "     <DataItem Format=\"XML\" NumberType=\"Float\" Precision=\"8\" Dimensions=\"3\">"
        "{:.17g} {:.17g} {:.17g}</DataItem>\n",
        grid.lower[2], grid.lower[1], grid.lower[0]);
    x += fmt::format(
        "     <DataItem Format=\"XML\" NumberType=\"Float\" Precision=\"8\" Dimensions=\"3\">"
        "{:.17g} {:.17g} {:.17g}</DataItem>\n",
        grid.spacing[2], grid.spacing[1], grid.spacing[0]);
    x += "    </Geometry>\n";
    for (const auto& f : s.fields) {
      const bool vec = is_vector_field(f);
      x += fmt::format("    <Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"Cell\">\n", f,
                       vec ? "Vector" : "Scalar");
      x += fmt::format(
          "     <DataItem Format=\"HDF\" NumberType=\"Float\" Precision=\"8\" Dimensions=\"{} {} "
          "{}{}\">{}:/{}</DataItem>\n",
          nz, ny, nx, vec ? " 3" : "", file, f);
      x += "    </Attribute>\n";
    }
    x += "   </Grid>\n";
  }
  x += "  </Grid>\n";
}

void add_particle_grids(std::string& x, const IndexTable& parts) {
  x += "  <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const auto& s : parts.rows) {
    const std::string file = "particles/" + snapshot_name(s.number);
    x += fmt::format("   <Grid Name=\"particles\" GridType=\"Uniform\">\n    <Time Value=\"{:.12g}\"/>\n",
                     s.time);
    x += fmt::format(
        "    <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{}\" NodesPerElement=\"1\"/>\n",
        s.count);
    x += "    <Geometry GeometryType=\"XYZ\">\n";
    x += fmt::format(
        "     <DataItem Format=\"HDF\" NumberType=\"Float\" Precision=\"8\" Dimensions=\"{} "
        "3\">{}:/position</DataItem>\n",
        s.count, file);
    x += "    </Geometry>\n";
    auto attr = [&](const std::string& name, bool vec, const char* type, int prec) {
      x += fmt::format("    <Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"Node\">\n", name,
                       vec ? "Vector" : "Scalar");
      x += fmt::format(
          "     <DataItem Format=\"HDF\" NumberType=\"{}\" Precision=\"{}\" "
          "Dimensions=\"{}{}\">{}:/{}</DataItem>\n",
          type, prec, s.count, vec ? " 3" : "", file, name);
      x += "    </Attribute>\n";
    };
    attr("id", false, "Int", 8);
    attr("species", false, "Int", 4);
    for (const auto& f : s.fields) {
      if (f == "position") continue;
      attr(f, f != "radius", "Float", 8);
    }
    x += "   </Grid>\n";
  }
  x += "  </Grid>\n";
}

}  // namespace

void write_xdmf(const std::string& dir, const GridGeometry& grid) {
  const FileLock lock(dir + "/run.xdmf.lock");
  std::string x;
  x += "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n";
  x += "<Xdmf Version=\"3.0\">\n <Domain>\n";
  if (const auto fluid = read_index(dir + "/fluid/index.csv"); !fluid.rows.empty())
    add_fluid_grids(x, fluid, grid);
  if (const auto parts = read_index(dir + "/particles/index.csv"); !parts.rows.empty())
    add_particle_grids(x, parts);
  x += " </Domain>\n</Xdmf>\n";
  atomic_write(dir + "/run.xdmf", x);
}

}  // namespace coflow::output
