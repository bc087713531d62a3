#include "particles/store/domain.hpp"

#include <algorithm>
#include <cmath>

#include "coflow/mpi_count.hpp"

namespace coflow::particles::store {

// MPI's counts and displacements are int: each, and the totals they add up
// to, are checked (coupler::mpi_count throws, telling the user to run on more
// ranks) instead of wrapping past 2^31 - 1 values.
void exchange(MPI_Comm comm, std::vector<std::vector<double>>& out, std::vector<double>& in) {
  const int size = static_cast<int>(out.size());
  std::vector<int> sc(size), rc(size), sd(size), rd(size);
  for (int r = 0; r < size; ++r) sc[r] = coupler::mpi_count(out[r].size(), "particle values for one rank");
  MPI_Alltoall(sc.data(), 1, MPI_INT, rc.data(), 1, MPI_INT, comm);
  std::vector<double> flat;
  std::size_t ts = 0, tr = 0;
  for (int r = 0; r < size; ++r) {
    sd[r] = static_cast<int>(ts);
    ts += static_cast<std::size_t>(sc[r]);
    rd[r] = static_cast<int>(tr);
    tr += static_cast<std::size_t>(rc[r]);
    flat.insert(flat.end(), out[r].begin(), out[r].end());
  }
  coupler::mpi_count(ts, "particle values sent by one rank");  // every displacement below it fits too
  coupler::mpi_count(tr, "particle values received by one rank");
  in.resize(tr);
  MPI_Alltoallv(flat.data(), sc.data(), sd.data(), MPI_DOUBLE, in.data(), rc.data(), rd.data(), MPI_DOUBLE, comm);
}

Domain::Domain(const coupler::Decomposition& dec, const double lower[3], const double upper[3],
               const std::array<bool, 3>& periodic, MPI_Comm comm)
    : dec_(dec), periodic_(periodic), comm_(comm) {
  for (int d = 0; d < 3; ++d) {
    lower_[d] = lower[d];
    upper_[d] = upper[d];
    cell_[d] = (upper[d] - lower[d]) / dec.cells()[d];
  }
  MPI_Comm_rank(comm, &rank_);
  MPI_Comm_size(comm, &size_);
}

int Domain::owner_of(const double* x) const {
  coupler::Index3 c{};
  for (int d = 0; d < 3; ++d) c[d] = grid_cell(x[d], lower_[d], upper_[d], dec_.cells()[d]);
  return dec_.owner(c);
}

std::vector<int> Domain::owners(const ParticleStore& s) const {
  std::vector<int> o(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) o[i] = owner_of(&s.arrays().x[3 * i]);
  return o;
}

bool Domain::near_block(const double* x, int r, double reach) const {
  const double lo[3] = {block_lo(r, 0), block_lo(r, 1), block_lo(r, 2)};
  const double hi[3] = {block_hi(r, 0), block_hi(r, 1), block_hi(r, 2)};
  for (int sx = -1; sx <= 1; ++sx)
    for (int sy = -1; sy <= 1; ++sy)
      for (int sz = -1; sz <= 1; ++sz) {
        const int sh[3] = {sx, sy, sz};
        bool in = true;
        for (int d = 0; d < 3 && in; ++d) {
          if (sh[d] != 0 && !periodic_[d]) in = false;
          const double y = x[d] + sh[d] * (upper_[d] - lower_[d]);
          in = in && y > lo[d] - reach && y < hi[d] + reach;
        }
        if (in) return true;
      }
  return false;
}

std::vector<double> Domain::send_leavers(const ParticleStore& s, const std::vector<int>& owners) const {
  std::vector<std::vector<double>> out(size_);
  for (std::size_t i = 0; i < s.size(); ++i)
    if (owners[i] != rank_) s.pack(i, migrates, out[owners[i]]);
  std::vector<double> in;
  exchange(comm_, out, in);
  return in;
}

void Domain::migrate(ParticleStore& s) const {
  const std::vector<int> o = owners(s);
  const std::vector<double> in = send_leavers(s, o);
  std::vector<char> stay(o.size());
  for (std::size_t i = 0; i < o.size(); ++i) stay[i] = o[i] == rank_;
  s.keep(stay);
  s.unpack_all(in, migrates);
  s.sort_by_id();
}

std::vector<double> Domain::send_ghosts(const ParticleStore& s, double reach) const {
  std::vector<std::vector<double>> out(size_);
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double* x = &s.arrays().x[3 * i];
    // Only a particle within reach of its own block's faces can be near another block.
    bool near = false;
    for (int d = 0; d < 3; ++d) near = near || x[d] - block_lo(rank_, d) < reach || block_hi(rank_, d) - x[d] < reach;
    if (!near) continue;
    for (int r = 0; r < size_; ++r)
      if (r != rank_ && near_block(x, r, reach)) s.pack(i, ghosts, out[r]);
  }
  std::vector<double> in;
  exchange(comm_, out, in);
  return in;
}

}  // namespace coflow::particles::store
