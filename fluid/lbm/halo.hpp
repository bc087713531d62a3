// The halo of one rank's block: a direct exchange with every face, edge and
// corner neighbour (persistent MPI requests, started each step). Only the
// populations a ghost is pulled for travel: towards direction d, those with
// e_q,a = d_a on every axis where d_a != 0 (5 of 19 through a face of D3Q19, 1
// through an edge, none through a corner). A periodic axis that is not split
// is copied within the block. W values per cell and population (2 where the
// red and blue populations of a cell sit side by side: value c of cell x's
// population q at q * stride + W x + c).
#pragma once

#include <mpi.h>

#include <array>
#include <utility>
#include <vector>

#include "coflow/decomposition.hpp"
#include "coflow/trace.hpp"
#include "coflow/wait.hpp"
#include "fluid/grid/neighbours.hpp"
#include "fluid/lbm/layout.hpp"

namespace coflow::fluid::lbm {

template <class L, int W = 1>
class HaloExchange {
 public:
  HaloExchange() = default;
  HaloExchange(const HaloExchange&) = delete;
  HaloExchange& operator=(const HaloExchange&) = delete;
  ~HaloExchange() {
    for (auto& h : links_) {
      if (h.send != MPI_REQUEST_NULL) MPI_Request_free(&h.send);
      if (h.recv != MPI_REQUEST_NULL) MPI_Request_free(&h.recv);
    }
  }

  // The neighbours of block `rank`; `lay` (its extent and ghosts now, its
  // padding by the first post) must outlive the exchange.
  void build(const Layout& lay, const coupler::Decomposition& dec, int rank, MPI_Comm comm);
  // Whether no other rank borders the block along x (its x ghosts are then
  // ready once post() returns).
  bool x_local() const { return x_local_; }
  // Start the exchange of the current populations f (copies within the block at once).
  void post(double* f, long stride);
  // Wait for the messages and fill the ghosts from them.
  void finish(double* f, long stride);

 private:
  struct Link {
    int rank = -1;
    int d[3] = {0, 0, 0};               // direction of the neighbour
    coupler::Box send_box, recv_box;    // local (ghost-offset) coordinates, owned-relative
    std::vector<int> send_q, recv_q;
    std::vector<double> send_buf, recv_buf;
    MPI_Request send = MPI_REQUEST_NULL, recv = MPI_REQUEST_NULL;
  };

  static std::vector<int> crossing(const int d[3], int sign) {
    std::vector<int> qs;
    for (int q = 0; q < L::Q; ++q) {
      bool all = true;
      for (int a = 0; a < 3; ++a) all = all && (d[a] == 0 || L::e[q][a] == sign * d[a]);
      if (all) qs.push_back(q);
    }
    return qs;
  }
  static Link link_to(const grid::Neighbour& n);
  void start(Link& h, MPI_Comm comm);

  template <class F>
  void for_box(const coupler::Box& bx, F&& f) const {
    for (long k = bx.lo[2]; k < bx.hi[2]; ++k)
      for (long j = bx.lo[1]; j < bx.hi[1]; ++j)
        for (long i = bx.lo[0]; i < bx.hi[0]; ++i) f(lay_->idx(i, j, k));
  }

  const Layout* lay_ = nullptr;
  std::vector<Link> links_;
  std::size_t remote_ = 0;  // links to other ranks
  bool x_local_ = false;
  std::vector<MPI_Request> requests_;
};

// The link to a neighbour of the fluid grid (grid/neighbours.hpp, one ghost
// layer) with the populations that cross to it and back.
template <class L, int W>
typename HaloExchange<L, W>::Link HaloExchange<L, W>::link_to(const grid::Neighbour& n) {
  Link h;
  h.rank = n.rank;
  for (int a = 0; a < 3; ++a) h.d[a] = n.d[a];
  h.send_box = n.send;
  h.recv_box = n.recv;
  h.send_q = crossing(h.d, 1);
  h.recv_q = crossing(h.d, -1);
  return h;
}

// Buffers and persistent requests of a link to another rank.
template <class L, int W>
void HaloExchange<L, W>::start(Link& h, MPI_Comm comm) {
  h.send_buf.resize(W * h.send_box.volume() * h.send_q.size());
  h.recv_buf.resize(W * h.recv_box.volume() * h.recv_q.size());
  const int tag_send = 500 + (h.d[0] + 1) + 3 * (h.d[1] + 1) + 9 * (h.d[2] + 1);
  const int tag_recv = 500 + (-h.d[0] + 1) + 3 * (-h.d[1] + 1) + 9 * (-h.d[2] + 1);
  MPI_Send_init(h.send_buf.data(), static_cast<int>(h.send_buf.size()), MPI_DOUBLE, h.rank, tag_send, comm, &h.send);
  MPI_Recv_init(h.recv_buf.data(), static_cast<int>(h.recv_buf.size()), MPI_DOUBLE, h.rank, tag_recv, comm, &h.recv);
  ++remote_;
}

template <class L, int W>
void HaloExchange<L, W>::build(const Layout& lay, const coupler::Decomposition& dec, int rank,
                               MPI_Comm comm) {
  lay_ = &lay;
  const long* g = lay.ghost;
  bool x_from_other = false;
  for (const grid::Neighbour& n : grid::neighbours(dec, rank, {g[0], g[1], g[2]})) {
    Link h = link_to(n);
    if (n.d[0] != 0 && n.d[1] == 0 && n.d[2] == 0 && h.rank != rank) x_from_other = true;
    if (h.send_q.empty()) continue;
    links_.push_back(std::move(h));
    if (links_.back().rank != rank) start(links_.back(), comm);  // else: copied in post()
  }
  x_local_ = g[0] && !x_from_other;
  requests_.resize(2 * remote_);
}

template <class L, int W>
void HaloExchange<L, W>::post(double* f, long stride) {
  coupler::Timer t(coupler::trace().halo_s);
  const long* n = lay_->extent;
  const long* P = lay_->padded;
  std::size_t m = 0;
  for (Link& h : links_) {
    if (h.send == MPI_REQUEST_NULL) {
      // To this rank itself: the face cells land in the ghosts on the
      // opposite side, one period away.
      const long shift = h.d[0] * n[0] + P[0] * (h.d[1] * n[1] + P[1] * h.d[2] * n[2]);
      for (const int q : h.send_q)
        for_box(h.send_box, [&](long x) {
          for (int c = 0; c < W; ++c) f[q * stride + W * (x - shift) + c] = f[q * stride + W * x + c];
        });
      continue;
    }
    MPI_Start(&h.recv);
    double* out = h.send_buf.data();
    for (const int q : h.send_q)
      for_box(h.send_box, [&](long x) {
        for (int c = 0; c < W; ++c) *out++ = f[q * stride + W * x + c];
      });
    MPI_Start(&h.send);
    requests_[2 * m] = h.recv;
    requests_[2 * m + 1] = h.send;
    ++m;
  }
}

template <class L, int W>
void HaloExchange<L, W>::finish(double* f, long stride) {
  if (remote_ == 0) return;
  coupler::wait_all(requests_, "the fluid halo exchange", &coupler::trace().halo_s);
  coupler::Timer t(coupler::trace().halo_s);
  for (Link& h : links_) {
    if (h.recv == MPI_REQUEST_NULL) continue;
    const double* in = h.recv_buf.data();
    for (const int q : h.recv_q)
      for_box(h.recv_box, [&](long x) {
        for (int c = 0; c < W; ++c) f[q * stride + W * x + c] = *in++;
      });
  }
}

}  // namespace coflow::fluid::lbm
