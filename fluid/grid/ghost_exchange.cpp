#include "fluid/grid/ghost_exchange.hpp"

#include <stdexcept>

#include "coflow/trace.hpp"
#include "coflow/wait.hpp"

namespace coflow::fluid::grid {

namespace {
int tag(const int d[3]) { return 700 + (d[0] + 1) + 3 * (d[1] + 1) + 9 * (d[2] + 1); }
}  // namespace

GhostExchange::GhostExchange(const coupler::Decomposition& dec, int rank, int width, int components, MPI_Comm comm)
    : block_(Block::of(dec, rank, width)), components_(components), rank_(rank), comm_(comm) {
  links_ = neighbours(dec, rank, block_.ghost);
  send_.resize(links_.size());
  recv_.resize(links_.size());
  for (std::size_t n = 0; n < links_.size(); ++n) {
    send_[n].resize(static_cast<std::size_t>(links_[n].send.volume()) * components);
    recv_[n].resize(static_cast<std::size_t>(links_[n].recv.volume()) * components);
  }
}

void GhostExchange::post(std::span<double> field) {
  if (field.size() != field_size()) throw std::logic_error("GhostExchange: field of the wrong size");
  requests_.clear();
  const int c = components_;
  for (std::size_t n = 0; n < links_.size(); ++n) {
    const Neighbour& h = links_[n];
    if (h.rank == rank_) {
      const long shift = block_.idx(h.period[0], h.period[1], h.period[2]) - block_.idx(0, 0, 0);
      for_box(h.send, [&](long x) {
        for (int q = 0; q < c; ++q) field[(x - shift) * c + q] = field[x * c + q];
      });
      continue;
    }
    // Ghosts on side -d of the neighbour are the cells sent towards +d; the
    // tag names the direction of travel.
    const int back[3] = {-h.d[0], -h.d[1], -h.d[2]};
    requests_.emplace_back();
    MPI_Irecv(recv_[n].data(), static_cast<int>(recv_[n].size()), MPI_DOUBLE, h.rank, tag(back), comm_,
              &requests_.back());
    double* out = send_[n].data();
    for_box(h.send, [&](long x) {
      for (int q = 0; q < c; ++q) *out++ = field[x * c + q];
    });
    requests_.emplace_back();
    MPI_Isend(send_[n].data(), static_cast<int>(send_[n].size()), MPI_DOUBLE, h.rank, tag(h.d), comm_,
              &requests_.back());
  }
}

void GhostExchange::finish(std::span<double> field) {
  if (requests_.empty()) return;
  coupler::wait_all(requests_, "the fluid grid's ghost exchange", &coupler::trace().halo_s);
  const int c = components_;
  for (std::size_t n = 0; n < links_.size(); ++n) {
    if (links_[n].rank == rank_) continue;
    const double* in = recv_[n].data();
    for_box(links_[n].recv, [&](long x) {
      for (int q = 0; q < c; ++q) field[x * c + q] = *in++;
    });
  }
  requests_.clear();
}

}  // namespace coflow::fluid::grid
