#include "coflow/exchange.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>
#include <exception>
#include <stdexcept>
#include <type_traits>

#include "coflow/session.hpp"
#include "coflow/trace.hpp"
#include "coflow/wait.hpp"

namespace coflow::coupler {

int mpi_count(std::size_t n, std::string_view what, std::string_view name) {
  if (n > static_cast<std::size_t>(INT_MAX))
    throw std::runtime_error(
        fmt::format("{}{}: {} elements in one MPI message, more than MPI's int count "
                    "(2^31 - 1) allows: run the components on more ranks",
                    what, name.empty() ? std::string() : fmt::format(" '{}'", name), n));
  return static_cast<int>(n);
}

namespace {

int remote_size_of(MPI_Comm inter) {
  int n = 0;
  MPI_Comm_remote_size(inter, &n);
  return n;
}

// Visits the cells of a box in z, y, x order.
template <class F>
void for_cells(const Box& b, F&& f) {
  for (long k = b.lo[2]; k < b.hi[2]; ++k)
    for (long j = b.lo[1]; j < b.hi[1]; ++j)
      for (long i = b.lo[0]; i < b.hi[0]; ++i) f(Index3{i, j, k});
}

Index3 sub(const Index3& a, const Index3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }

// Calls f(std::integral_constant<int, N>{}) with N the values per cell where
// the components use 3 to 5, else with N = 0 (f then takes the count at run
// time): with N known the per-cell copies of the sparse records are inlined
// instead of a library call each (perf put the sand demo's immersed and fluid
// ranks' largest exchange items on those calls).
template <class F>
void with_components(int nc, F&& f) {
  switch (nc) {
    case 3:
      return f(std::integral_constant<int, 3>{});
    case 4:
      return f(std::integral_constant<int, 4>{});
    case 5:
      return f(std::integral_constant<int, 5>{});
    default:
      return f(std::integral_constant<int, 0>{});
  }
}

}  // namespace

FieldExchange::FieldExchange(MPI_Comm inter, Role role, const Decomposition& mine, int my_rank,
                             const Decomposition& remote, FieldSpec spec, int tag)
    : inter_(inter), role_(role), spec_(std::move(spec)), tag_(tag), mine_(mine), remote_(remote) {
  if (mine.cells() != remote.cells())
    throw std::invalid_argument("field exchange between different grids");
  owned_ = mine.block(my_rank);
  local_box_ = owned_.grown(mine.ghost(spec_.ghost));
  build(mine, my_rank, remote);
}

FieldExchange::~FieldExchange() {
  // Unwinding towards Session::fail (an error on this rank): waiting here for
  // a partner that may never receive would hold the run's failure back by
  // up to coupling.timeout, and blame the partner's timeout instead. The
  // messages are left to MPI with this exchange's buffers (packed, sparse
  // and reply), which are not freed: the process is about to abort. A
  // contiguous send reads the caller's own array, which may already be gone
  // (as it could be during the wait before).
  if (std::uncaught_exceptions() > 0) {
    [[maybe_unused]] auto* left = new std::vector<Peer>(std::move(peers_));
    [[maybe_unused]] auto* replies = new std::vector<double>(std::move(reply_out_));
    return;
  }
  // Outstanding sends must complete before their buffers go away.
  try {
    flush();
  } catch (...) {
  }
  for (auto& p : peers_)
    if (p.contiguous < 0 && p.request != MPI_REQUEST_NULL) MPI_Request_free(&p.request);
}

long FieldExchange::local_index(const Index3& g) const {
  const Index3 l = sub(g, local_box_.lo);
  return (l[2] * local_box_.extent(1) + l[1]) * local_box_.extent(0) + l[0];
}

// The map. For a consistent field, data flows from the sender's owned block to
// the receiver's grown (ghost-including) block; for a conservative field, from
// the sender's grown block to the receiver's owned block. Periodic images are
// handled by shifting boxes by multiples of the domain size. Both sides walk the
// same (sender, receiver, shift) regions in the same order.
void FieldExchange::build(const Decomposition& mine, int my_rank, const Decomposition& remote) {
  const bool sender = role_ == Role::sender;
  const Decomposition& sdec = sender ? mine : remote;
  const Decomposition& rdec = sender ? remote : mine;
  const Index3 g = mine.ghost(spec_.ghost);
  // The images are one period away (image_shifts): a ghost layer wider than a
  // periodic axis would reach cells no shift maps, left stale (consistent) or
  // lost (conservative) without a word.
  for (int d = 0; d < 3; ++d)
    if (mine.periodic()[d] && g[d] > mine.cells()[d])
      throw std::invalid_argument(
          fmt::format("field '{}': a ghost layer of {} cells is wider than the periodic axis {} "
                      "of {} cells",
                      spec_.name, g[d], "xyz"[d], mine.cells()[d]));
  const auto shifts = mine.image_shifts();
  const bool cons = spec_.transfer == Transfer::conservative;
  const int npeer = remote.ranks();

  for (int p = 0; p < npeer; ++p) {
    const int s = sender ? my_rank : p;
    const int r = sender ? p : my_rank;
    // Source region (sender frame, unwrapped) and target region (receiver frame).
    const Box src = cons ? sdec.clip(sdec.block(s).grown(g)) : sdec.block(s);
    const Box dst = cons ? rdec.block(r) : rdec.clip(rdec.block(r).grown(g));
    Peer peer;
    peer.rank = p;
    peer.remote_local = rdec.block(r).grown(g);
    for (const auto& sh : shifts) {
      // Consistent: region in receiver frame = src shifted ∩ dst.
      // Conservative: region in sender frame = src ∩ dst shifted.
      const Box region = cons ? intersect(src, dst.shifted(sh)) : intersect(src.shifted(sh), dst);
      if (region.empty()) continue;
      for_cells(region, [&](const Index3& c) {
        Index3 local_cell;
        if (cons)  // c in sender frame; receiver cell is c - shift
          local_cell = sender ? c : sub(c, sh);
        else  // c in receiver frame; sender cell is c - shift
          local_cell = sender ? sub(c, sh) : c;
        peer.cells.push_back(local_index(local_cell));
      });
    }
    if (peer.cells.empty()) continue;
    // A consistent message that is one contiguous run of cells goes straight
    // from/to the user's array: no packing.
    bool run = !cons;
    for (std::size_t i = 1; run && i < peer.cells.size(); ++i) run = peer.cells[i] == peer.cells[0] + static_cast<long>(i);
    if (run)
      peer.contiguous = peer.cells[0];
    else
      peer.buffer.resize(peer.cells.size() * spec_.components);
    peers_.push_back(std::move(peer));
  }
  requests_.resize(peers_.size(), MPI_REQUEST_NULL);
  peer_of_.assign(remote.ranks(), -1);
  for (std::size_t i = 0; i < peers_.size(); ++i) peer_of_[peers_[i].rank] = static_cast<int>(i);
  for (std::size_t i = 0; i < peers_.size(); ++i) {
    auto& p = peers_[i];
    if (p.contiguous >= 0) continue;  // posted per call on the user's array
    const int n = mpi_count(p.buffer.size(), "field", spec_.name);
    if (sender)
      MPI_Send_init(p.buffer.data(), n, MPI_DOUBLE, p.rank, tag_, inter_, &p.request);
    else
      MPI_Recv_init(p.buffer.data(), n, MPI_DOUBLE, p.rank, tag_, inter_, &p.request);
  }
}

void FieldExchange::flush() {
  if (sends_pending_) {
    for (std::size_t i = 0; i < peers_.size(); ++i) requests_[i] = peers_[i].request;
    wait_all(requests_, fmt::format("the delivery of field '{}'", spec_.name));
    for (std::size_t i = 0; i < peers_.size(); ++i) peers_[i].request = requests_[i];
    sends_pending_ = false;
  }
  if (!sparse_requests_.empty()) {
    wait_all(sparse_requests_, fmt::format("the delivery of sparse field '{}'", spec_.name));
    sparse_requests_.clear();
  }
  if (!reply_requests_.empty()) {
    wait_all(reply_requests_, fmt::format("the delivery of the replies to sparse field '{}'", spec_.name));
    reply_requests_.clear();
  }
}

void FieldExchange::send(std::span<const double> local) {
  if (role_ != Role::sender) throw std::logic_error("send() on the receiving side");
  if (local.size() != local_size())
    throw std::invalid_argument(fmt::format("field '{}': local array has {} values, expected {}",
                                            spec_.name, local.size(), local_size()));
  flush();
  Timer t(trace().exchange_s);
  const int nc = spec_.components;
  for (auto& p : peers_) {
    const std::size_t n = p.cells.size() * nc;
    if (p.contiguous >= 0) {
      // The caller keeps `local` unchanged until the next send() or flush().
      MPI_Isend(local.data() + p.contiguous * nc, mpi_count(n, "field", spec_.name), MPI_DOUBLE, p.rank, tag_,
                inter_, &p.request);
    } else {
      double* out = p.buffer.data();
      for (long c : p.cells) {
        const double* in = local.data() + c * nc;
        for (int k = 0; k < nc; ++k) *out++ = in[k];
      }
      MPI_Start(&p.request);
    }
    trace().bytes_sent += n * sizeof(double);
  }
  ++trace().exchanges;
  sends_pending_ = !peers_.empty();
}

void FieldExchange::receive(std::span<double> local) {
  if (role_ != Role::receiver) throw std::logic_error("receive() on the sending side");
  if (local.size() != local_size())
    throw std::invalid_argument(fmt::format("field '{}': local array has {} values, expected {}",
                                            spec_.name, local.size(), local_size()));
  const int nc = spec_.components;
  const bool cons = spec_.transfer == Transfer::conservative;
  {
    Timer t(trace().exchange_s);
    for (std::size_t i = 0; i < peers_.size(); ++i) {
      auto& p = peers_[i];
      if (p.contiguous >= 0)
        MPI_Irecv(local.data() + p.contiguous * nc, mpi_count(p.cells.size() * nc, "field", spec_.name),
                  MPI_DOUBLE, p.rank, tag_, inter_, &p.request);
      else
        MPI_Start(&p.request);
      requests_[i] = p.request;
    }
    if (cons)
      for_cells(owned_, [&](const Index3& c) {
        double* v = local.data() + local_index(c) * nc;
        for (int k = 0; k < nc; ++k) v[k] = 0.0;
      });
  }
  wait_all(requests_, fmt::format("field '{}'", spec_.name));
  for (std::size_t i = 0; i < peers_.size(); ++i) peers_[i].request = requests_[i];
  Timer t(trace().exchange_s);
  for (auto& p : peers_) {
    trace().bytes_received += p.cells.size() * nc * sizeof(double);
    if (p.contiguous >= 0) continue;  // already in place
    const double* in = p.buffer.data();
    if (cons) {
      for (long c : p.cells) {
        double* v = local.data() + c * nc;
        for (int k = 0; k < nc; ++k) v[k] += *in++;
      }
    } else {
      for (long c : p.cells) {
        double* v = local.data() + c * nc;
        for (int k = 0; k < nc; ++k) v[k] = *in++;
      }
    }
  }
  ++trace().exchanges;
}

// Sparse messages: a sequence of records {int32 cell index in the receiver's
// local array; double values[nc]}, per peer in the order of `cells`.
void FieldExchange::send_sparse(std::span<const Index3> cells, std::span<const double> values) {
  if (role_ != Role::sender) throw std::logic_error("send_sparse() on the receiving side");
  const int nc = spec_.components;
  if (values.size() != cells.size() * nc)
    throw std::invalid_argument(fmt::format("field '{}': {} values for {} cells", spec_.name,
                                            values.size(), cells.size()));
  if (cells.size() > static_cast<std::size_t>(INT32_MAX))
    throw std::invalid_argument(
        fmt::format("field '{}': {} sparse cells in one message", spec_.name, cells.size()));
  flush();
  Timer t(trace().exchange_s);
  pack_sparse(cells, values);
  sparse_requests_.resize(peers_.size());
  for (std::size_t i = 0; i < peers_.size(); ++i) {
    auto& p = peers_[i];
    MPI_Isend(p.sparse.data(), mpi_count(p.sparse_used, "sparse field (bytes)", spec_.name), MPI_BYTE, p.rank,
              tag_ + 1, inter_, &sparse_requests_[i]);
    trace().bytes_sent += p.sparse_used;
  }
  ++trace().exchanges;
}

// Each cell's record into the buffer of every peer it goes to (the buffers
// only grow, so that they are not zero-filled record by record), and the
// cells sent to each peer, for the replies.
void FieldExchange::pack_sparse(std::span<const Index3> cells, std::span<const double> values) {
  for (auto& p : peers_) {
    if (p.remote_local.volume() > INT32_MAX)  // sparse records carry an int32 index there
      throw std::invalid_argument(
          fmt::format("sparse field '{}': {} cells on rank {} of the receiving side (at "
                      "most 2^31 - 1): run it on more ranks",
                      spec_.name, p.remote_local.volume(), p.rank));
    p.sparse_used = 0, p.sent_count = 0;
  }
  sparse_sent_ = cells.size();
  const auto check_inside = [&] {
    for (const Index3& c : cells)
      if (!local_box_.contains(c))
        throw std::invalid_argument(fmt::format("field '{}': sparse cell ({}, {}, {}) outside the local box",
                                                spec_.name, c[0], c[1], c[2]));
  };
  if (spec_.transfer == Transfer::conservative) {
    check_inside();
    for (std::size_t n = 0; n < cells.size(); ++n) {
      const Index3& c = cells[n];
      if (mine_.clip(Box{c, {c[0] + 1, c[1] + 1, c[2] + 1}}).empty()) continue;  // outside a wall
      const Index3 w = mine_.wrap(c);
      const int owner = remote_.owner(w);
      if (owner >= 0 && peer_of_[owner] >= 0) append_sparse(peers_[peer_of_[owner]], w, n, values);
    }
    return;
  }
  build_routes();  // consistent: only owned values are sent, to every image in a peer's reach
  if (pack_routes(cells, values)) check_inside();  // names the first cell outside
}

// The record {int32 index in the receiver's local box, nc values} of input
// cell n at `cell` (the receiver's frame) at the end of p's message.
void FieldExchange::append_sparse(Peer& p, const Index3& cell, std::size_t n,
                                  std::span<const double> values) {
  const int nc = spec_.components;
  const std::size_t rec = sizeof(std::int32_t) + nc * sizeof(double);
  if (p.sent_count == p.sent.size()) p.sent.resize(p.sent.size() + p.sent.size() / 2 + 16);
  p.sent[p.sent_count++] = static_cast<std::int32_t>(n);
  const std::size_t at = p.sparse_used;
  if (at + rec > p.sparse.size()) p.sparse.resize(std::max(at + rec, p.sparse.size() + p.sparse.size() / 2));
  p.sparse_used = at + rec;
  const Box& b = p.remote_local;  // the cell's index there, as the receiver's local_index()
  const auto index = static_cast<std::int32_t>(
      ((cell[2] - b.lo[2]) * b.extent(1) + (cell[1] - b.lo[1])) * b.extent(0) + (cell[0] - b.lo[0]));
  std::memcpy(p.sparse.data() + at, &index, sizeof index);
  std::memcpy(p.sparse.data() + at + sizeof index, values.data() + n * nc, nc * sizeof(double));
}

// Every peer's message along the routes, in one pass over the cells: for each
// peer the same records in the same order as append_sparse cell by cell
// (cells in input order, each along that peer's routes in order). Each
// peer's write position is held in `cursors_` (the records are byte copies,
// after which the compiler would reload a Peer's members). Returns whether a
// cell lies outside the local box (tested on the way, without a branch).
bool FieldExchange::pack_routes(std::span<const Index3> cells, std::span<const double> values) {
  bool outside = false;
  with_components(spec_.components, [&]<int N>(std::integral_constant<int, N>) {
    const std::size_t nc = N > 0 ? N : spec_.components, rec = sizeof(std::int32_t) + nc * sizeof(double);
    cursors_.resize(peers_.size());
    for (std::size_t i = 0; i < peers_.size(); ++i) reserve_records(i, 0, rec);
    const Box local = local_box_;
    for (std::size_t n = 0; n < cells.size(); ++n) {
      const Index3& c = cells[n];
      for (int d = 0; d < 3; ++d) outside |= (c[d] < local.lo[d]) | (c[d] >= local.hi[d]);
      for (const Route& r : routes_) {
        if (!r.from.contains(c)) continue;
        Cursor& k = cursors_[static_cast<std::size_t>(r.peer)];
        if (k.out == k.end) k = grow_records(static_cast<std::size_t>(r.peer), rec);
        const auto index = static_cast<std::int32_t>(
            ((c[2] + k.shift_lo[2] + r.shift[2]) * k.extent[1] + (c[1] + k.shift_lo[1] + r.shift[1])) *
                k.extent[0] +
            (c[0] + k.shift_lo[0] + r.shift[0]));
        std::memcpy(k.out, &index, sizeof index);
        std::memcpy(k.out + sizeof index, values.data() + n * nc, nc * sizeof(double));
        k.out += rec;
        *k.sent++ = static_cast<std::int32_t>(n);
        if (routes_disjoint_) break;  // no cell goes two ways
      }
    }
    for (std::size_t i = 0; i < peers_.size(); ++i) {
      peers_[i].sparse_used = static_cast<std::size_t>(cursors_[i].out - peers_[i].sparse.data());
      peers_[i].sent_count = static_cast<std::size_t>(cursors_[i].sent - peers_[i].sent.data());
    }
  });
  return outside;
}

// Peer i's buffers with room for at least `records` records of `rec` bytes
// from its current end (they only grow, and keep the room of earlier
// windows), and its cursor there.
void FieldExchange::reserve_records(std::size_t i, std::size_t records, std::size_t rec) {
  Peer& p = peers_[i];
  const std::size_t used = p.sparse_used, count = p.sent_count;
  if (p.sparse.size() < used + records * rec) p.sparse.resize(used + records * rec);
  if (p.sent.size() < count + records) p.sent.resize(count + records);
  const Box& b = p.remote_local;
  Cursor& k = cursors_[i];
  const std::size_t room = std::min((p.sparse.size() - used) / rec, p.sent.size() - count);
  k.out = p.sparse.data() + used;
  k.end = k.out + room * rec;
  k.sent = p.sent.data() + count;
  k.shift_lo = {-b.lo[0], -b.lo[1], -b.lo[2]};
  k.extent = {b.extent(0), b.extent(1), b.extent(2)};
}

// Peer i's cursor at the end of its full buffers, with room for as many records again.
FieldExchange::Cursor FieldExchange::grow_records(std::size_t i, std::size_t rec) {
  Peer& p = peers_[i];
  p.sparse_used = static_cast<std::size_t>(cursors_[i].out - p.sparse.data());
  p.sent_count = static_cast<std::size_t>(cursors_[i].sent - p.sent.data());
  reserve_records(i, std::max<std::size_t>(p.sent_count, 16), rec);
  return cursors_[i];
}

// The consistent sparse routes (Route), once: what pack_sparse tested per
// cell before, for every peer and image shift, now per cell only for the
// pairs that can take a cell at all (a few of up to 27 x peers).
void FieldExchange::build_routes() {
  if (routes_built_) return;
  const Index3 g = mine_.ghost(spec_.ghost);
  for (std::size_t i = 0; i < peers_.size(); ++i) {
    const Box dst = remote_.clip(remote_.block(peers_[i].rank).grown(g));
    for (const auto& sh : mine_.image_shifts()) {
      const Box from = intersect(owned_, dst.shifted({-sh[0], -sh[1], -sh[2]}));
      if (!from.empty()) routes_.push_back({static_cast<int>(i), sh, from});
    }
  }
  routes_disjoint_ = true;
  for (std::size_t a = 0; a < routes_.size(); ++a)
    for (std::size_t b = a + 1; b < routes_.size(); ++b)
      routes_disjoint_ = routes_disjoint_ && intersect(routes_[a].from, routes_[b].from).empty();
  routes_built_ = true;
}

void FieldExchange::receive_sparse(std::vector<long>& cells, std::vector<double>& values) {
  if (role_ != Role::receiver) throw std::logic_error("receive_sparse() on the sending side");
  const int nc = spec_.components;
  const std::size_t rec = sizeof(std::int32_t) + nc * sizeof(double);
  std::size_t total = 0;
  for (auto& p : peers_) {
    MPI_Status st = wait_probe(p.rank, tag_ + 1, inter_, fmt::format("sparse field '{}'", spec_.name));
    Timer t(trace().exchange_s);
    int bytes = 0;
    MPI_Get_count(&st, MPI_BYTE, &bytes);
    p.sparse.resize(bytes);
    MPI_Recv(p.sparse.data(), bytes, MPI_BYTE, p.rank, tag_ + 1, inter_, MPI_STATUS_IGNORE);
    if (static_cast<std::size_t>(bytes) % rec != 0)
      throw std::runtime_error(
          fmt::format("sparse field '{}': {} bytes from rank {} are no whole number of {}-byte "
                      "records (the two sides disagree on the values per cell)",
                      spec_.name, bytes, p.rank, rec));
    trace().bytes_received += bytes;
    p.received = bytes / rec;
    total += p.received;
  }
  Timer t(trace().exchange_s);
  // Resized, not cleared first: a vector of last window's length is not
  // zero-filled again before every element is written.
  cells.resize(total);
  values.resize(total * nc);
  std::size_t first = 0;
  for (const auto& p : peers_) {
    unpack_sparse(p, cells.data() + first, values.data() + first * nc);
    first += p.received;
  }
  ++trace().exchanges;
}

// Peer p's received records into `cells` (local indices, checked) and
// `values` (nc a cell).
void FieldExchange::unpack_sparse(const Peer& p, long* cells, double* values) const {
  with_components(spec_.components, [&]<int N>(std::integral_constant<int, N>) {
    const int nc = N > 0 ? N : spec_.components;
    const std::size_t rec = sizeof(std::int32_t) + nc * sizeof(double);
    const long volume = local_box_.volume();
    const std::byte* in = p.sparse.data();
    for (std::size_t i = 0; i < p.received; ++i, in += rec) {
      std::int32_t index = 0;
      std::memcpy(&index, in, sizeof index);
      if (index < 0 || index >= volume)
        throw std::runtime_error(
            fmt::format("sparse field '{}': cell index {} from rank {} outside the local "
                        "array of {} cells (the two sides disagree on the layout)",
                        spec_.name, index, p.rank, volume));
      cells[i] = index;
      std::memcpy(values + i * nc, in + sizeof index, nc * sizeof(double));
    }
  });
}

void FieldExchange::check_replies(const char* call, int components) const {
  if (components < 1)
    throw std::invalid_argument(
        fmt::format("field '{}': {} with {} components", spec_.name, call, components));
  if (spec_.transfer == Transfer::consistent && spec_.ghost > 0)
    throw std::logic_error(
        fmt::format("field '{}': {} on a consistent exchange with a ghost layer (a cell "
                    "may reach several ranks)",
                    spec_.name, call));
}

// One message per peer that sent a sparse message (empty ones too), tag + 2.
void FieldExchange::reply_sparse(std::span<const double> results, int components) {
  start_replies(results.size(), components);
  Timer t(trace().exchange_s);
  reply_out_.assign(results.begin(), results.end());
  send_replies(components);
}

// The same without the copy: `results` is sent from where it is, and comes
// back holding an earlier buffer.
void FieldExchange::reply_sparse(std::vector<double>&& results, int components) {
  start_replies(results.size(), components);
  Timer t(trace().exchange_s);
  std::swap(reply_out_, results);
  send_replies(components);
}

void FieldExchange::start_replies(std::size_t values, int components) {
  if (role_ != Role::receiver) throw std::logic_error("reply_sparse() on the sending side");
  check_replies("reply_sparse()", components);
  std::size_t total = 0;
  for (const auto& p : peers_) total += p.received;
  if (values != total * components)
    throw std::invalid_argument(
        fmt::format("field '{}': {} reply values for {} cells received", spec_.name, values, total));
  flush();  // the last replies' buffer
}

void FieldExchange::send_replies(int components) {
  reply_requests_.resize(peers_.size());
  const double* from = reply_out_.data();
  for (std::size_t i = 0; i < peers_.size(); ++i) {
    const std::size_t n = peers_[i].received * components;
    MPI_Isend(from, mpi_count(n, "replies of field", spec_.name), MPI_DOUBLE, peers_[i].rank, tag_ + 2,
              inter_, &reply_requests_[i]);
    from += n;
    trace().bytes_sent += n * sizeof(double);
  }
  ++trace().exchanges;
}

void FieldExchange::receive_replies(std::span<double> results, int components) {
  if (role_ != Role::sender) throw std::logic_error("receive_replies() on the receiving side");
  check_replies("receive_replies()", components);
  if (results.size() != sparse_sent_ * components)
    throw std::invalid_argument(fmt::format("field '{}': room for {} reply values, {} cells sent", spec_.name,
                                            results.size(), sparse_sent_));
  for (auto& p : peers_) {  // each rank's reply, checked for its length
    const MPI_Status st =
        wait_probe(p.rank, tag_ + 2, inter_, fmt::format("the replies to sparse field '{}'", spec_.name));
    Timer t(trace().exchange_s);
    int count = 0;
    MPI_Get_count(&st, MPI_DOUBLE, &count);
    if (static_cast<std::size_t>(count) != p.sent_count * components)
      throw std::runtime_error(
          fmt::format("sparse field '{}': rank {} replied with {} values for {} cells of {} "
                      "values (the two sides disagree on the protocol)",
                      spec_.name, p.rank, count, p.sent_count, components));
    p.reply.resize(static_cast<std::size_t>(count));
    MPI_Recv(p.reply.data(), count, MPI_DOUBLE, p.rank, tag_ + 2, inter_, MPI_STATUS_IGNORE);
  }
  Timer t(trace().exchange_s);
  // A cell reaches one rank at most (check_replies), so where as many cells
  // went out as were given, every one has its reply and no zeros are needed.
  std::size_t answered = 0;
  for (const auto& p : peers_) answered += p.sent_count;
  if (answered != sparse_sent_) std::fill(results.begin(), results.end(), 0.0);
  with_components(components, [&]<int N>(std::integral_constant<int, N>) {
    const std::size_t nc = N > 0 ? N : components;
    for (const auto& p : peers_) {
      trace().bytes_received += p.reply.size() * sizeof(double);
      const double* in = p.reply.data();
      for (std::size_t i = 0; i < p.sent_count; ++i, in += nc)
        std::memcpy(results.data() + static_cast<std::size_t>(p.sent[i]) * nc, in, nc * sizeof(double));
    }
  });
  ++trace().exchanges;
}

}  // namespace coflow::coupler

// ------------------------------------------------------------ PointExchange --

namespace coflow::coupler {

namespace {

// Time inside a point-exchange call, less what its collective waits already
// booked as waiting (the two must not overlap in the summary).
class ExchangeTimer {
 public:
  ExchangeTimer() : start_(now()), wait0_(trace().wait_s) {}
  ~ExchangeTimer() { trace().exchange_s += (now() - start_) - (trace().wait_s - wait0_); }
  ExchangeTimer(const ExchangeTimer&) = delete;
  ExchangeTimer& operator=(const ExchangeTimer&) = delete;

 private:
  double start_, wait0_;
};

}  // namespace

PointExchange::PointExchange(MPI_Comm inter, Role role, const Decomposition& destination,
                             std::array<double, 3> lower, std::array<double, 3> spacing,
                             std::size_t record_bytes, std::size_t result_bytes, int tag, int ghost)
    : inter_(inter),
      role_(role),
      dest_(destination),
      lower_(lower),
      spacing_(spacing),
      record_bytes_(record_bytes),
      result_bytes_(result_bytes),
      tag_(tag),
      ghost_(ghost) {
  remote_size_ = remote_size_of(inter);
  send_counts_.assign(remote_size_, 0);
  recv_counts_.assign(remote_size_, 0);
  send_displs_.assign(remote_size_, 0);
  recv_displs_.assign(remote_size_, 0);
  routed_.resize(remote_size_);
}

namespace {

// Collective on the intercommunicator, waited on with the deadline.
void alltoall_counts(const std::vector<int>& send, std::vector<int>& recv, MPI_Comm inter,
                     const char* what) {
  MPI_Request r;
  MPI_Ialltoall(send.data(), 1, MPI_INT, recv.data(), 1, MPI_INT, inter, &r);
  wait_one(r, what);
}

void alltoallv_bytes(const std::vector<std::byte>& out, const std::vector<int>& sc,
                     const std::vector<int>& sd, std::vector<std::byte>& in,
                     const std::vector<int>& rc, const std::vector<int>& rd, MPI_Comm inter,
                     const char* what) {
  MPI_Request r;
  MPI_Ialltoallv(out.data(), sc.data(), sd.data(), MPI_BYTE, in.data(), rc.data(), rd.data(),
                 MPI_BYTE, inter, &r);
  wait_one(r, what);
}

void prefix(const std::vector<int>& counts, std::vector<int>& displs) {
  long total = 0;
  for (std::size_t i = 0; i < counts.size(); ++i) {
    displs[i] = static_cast<int>(total);
    total += counts[i];
  }
  mpi_count(static_cast<std::size_t>(total), "one point exchange, all peers together (bytes)");
}

long total_of(const std::vector<int>& counts) {
  long t = 0;
  for (int c : counts) t += c;
  return t;
}

}  // namespace

void PointExchange::send(std::span<const std::byte> records,
                         std::span<const std::array<double, 3>> positions) {
  if (role_ != Role::origin) throw std::logic_error("PointExchange::send on the destination side");
  if (records.size() != positions.size() * record_bytes_)
    throw std::invalid_argument("point exchange: records and positions differ in count");
  ExchangeTimer t;
  nrecords_ = positions.size();
  for (auto& r : routed_) r.clear();
  const Index3 g = dest_.ghost(ghost_);
  const auto shifts = dest_.image_shifts();
  std::vector<int> extra;  // reused per record
  for (std::size_t n = 0; n < positions.size(); ++n) {
    const auto& x = positions[n];
    // A position that is not finite has no cell (its cast to a cell index is
    // undefined): the run stops, here where it is sent.
    if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
      throw SolverError(
          fmt::format("point exchange: record {} of this rank has a position that is not finite "
                      "({}, {}, {})",
                      n, x[0], x[1], x[2]));
    Index3 c{};
    for (int d = 0; d < 3; ++d) {
      // Clamped before the cast (a finite but huge position, e.g. a particle
      // blown up, would not fit a long): the faces' cells off periodic axes.
      const double f = std::floor((positions[n][d] - lower_[d]) / spacing_[d]);
      const double top = static_cast<double>(dest_.cells()[d] - 1);
      c[d] = static_cast<long>(dest_.periodic()[d] ? std::clamp(f, -1e15, 1e15) : std::clamp(f, 0.0, top));
    }
    const int owner = dest_.owner(c);
    routed_[owner].push_back(static_cast<std::uint32_t>(n));
    if (ghost_ == 0) continue;
    // Ghost copies: only records near the owner's block boundary can be in
    // another rank's ghost layer.
    const Box& ob = dest_.block(owner);
    const Index3 w = dest_.wrap(c);
    bool near = false;
    for (int d = 0; d < 3; ++d) near = near || w[d] - ob.lo[d] < g[d] || ob.hi[d] - 1 - w[d] < g[d];
    if (!near) continue;
    for (int r = 0; r < dest_.ranks(); ++r) {
      if (r == owner) continue;
      const Box gb = dest_.block(r).grown(g);
      for (const auto& sh : shifts) {
        if (gb.contains(Index3{w[0] + sh[0], w[1] + sh[1], w[2] + sh[2]})) {
          routed_[r].push_back(static_cast<std::uint32_t>(n) | 0x80000000u);  // ghost copy
          break;
        }
      }
    }
  }
  const std::size_t rec = record_bytes_ + 1;
  for (int r = 0; r < remote_size_; ++r)
    send_counts_[r] = mpi_count(routed_[r].size() * rec, "point records (bytes)");
  prefix(send_counts_, send_displs_);
  out_.resize(total_of(send_counts_));
  for (int r = 0; r < remote_size_; ++r) {
    std::byte* o = out_.data() + send_displs_[r];
    for (std::uint32_t tagged : routed_[r]) {
      const std::uint32_t n = tagged & 0x7fffffffu;
      *o++ = std::byte{static_cast<unsigned char>((tagged & 0x80000000u) ? 0 : 1)};
      std::memcpy(o, records.data() + n * record_bytes_, record_bytes_);
      o += record_bytes_;
    }
  }
  alltoall_counts(send_counts_, recv_counts_, inter_, "point-exchange counts");
  prefix(recv_counts_, recv_displs_);
  in_.resize(total_of(recv_counts_));
  alltoallv_bytes(out_, send_counts_, send_displs_, in_, recv_counts_, recv_displs_, inter_,
                  "point records");
  trace().bytes_sent += out_.size();
  ++trace().exchanges;
}

void PointExchange::receive(std::vector<std::byte>& records, std::vector<std::uint8_t>& owned) {
  if (role_ != Role::destination) throw std::logic_error("PointExchange::receive on the origin side");
  ExchangeTimer t;
  std::fill(send_counts_.begin(), send_counts_.end(), 0);
  prefix(send_counts_, send_displs_);
  out_.clear();
  alltoall_counts(send_counts_, recv_counts_, inter_, "point-exchange counts");
  prefix(recv_counts_, recv_displs_);
  in_.resize(total_of(recv_counts_));
  alltoallv_bytes(out_, send_counts_, send_displs_, in_, recv_counts_, recv_displs_, inter_,
                  "point records");
  const std::size_t rec = record_bytes_ + 1;
  // Exchanges are told apart by their order on the intercommunicator only: a
  // partner calling another exchange here (records of another size) is caught.
  for (int r = 0; r < remote_size_; ++r)
    if (static_cast<std::size_t>(recv_counts_[r]) % rec != 0)
      throw SolverError(
          fmt::format("point exchange: {} bytes from partner rank {} are not whole records of {} "
                      "bytes: the two sides called different exchanges (their order must match)",
                      recv_counts_[r], r, record_bytes_));
  const std::size_t n = in_.size() / rec;
  records.resize(n * record_bytes_);
  owned.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    owned[i] = static_cast<std::uint8_t>(in_[i * rec]);
    std::memcpy(records.data() + i * record_bytes_, in_.data() + i * rec + 1, record_bytes_);
  }
  nrecords_ = n;
  // Remember per-origin counts for the way back.
  for (int r = 0; r < remote_size_; ++r) routed_[r].assign(recv_counts_[r] / rec, 0);
  trace().bytes_received += in_.size();
  ++trace().exchanges;
}

void PointExchange::send_results(std::span<const std::byte> results) {
  if (role_ != Role::destination) throw std::logic_error("send_results on the origin side");
  if (results.size() != nrecords_ * result_bytes_)
    throw std::invalid_argument("point exchange: one result per received record is needed");
  ExchangeTimer t;
  for (int r = 0; r < remote_size_; ++r)
    send_counts_[r] = mpi_count(routed_[r].size() * result_bytes_, "point results (bytes)");
  prefix(send_counts_, send_displs_);
  out_.assign(results.begin(), results.end());
  std::fill(recv_counts_.begin(), recv_counts_.end(), 0);
  prefix(recv_counts_, recv_displs_);
  in_.clear();
  alltoall_counts(send_counts_, recv_counts_, inter_, "point-result counts");
  alltoallv_bytes(out_, send_counts_, send_displs_, in_, recv_counts_, recv_displs_, inter_,
                  "point results");
  trace().bytes_sent += out_.size();
}

void PointExchange::receive_results(std::span<std::byte> results,
                                    void (*combine)(std::byte*, const std::byte*)) {
  if (role_ != Role::origin) throw std::logic_error("receive_results on the destination side");
  if (results.size() != nrecords_ * result_bytes_)
    throw std::invalid_argument("point exchange: results must hold one entry per sent record");
  ExchangeTimer t;
  std::fill(send_counts_.begin(), send_counts_.end(), 0);
  prefix(send_counts_, send_displs_);
  out_.clear();
  alltoall_counts(send_counts_, recv_counts_, inter_, "point-result counts");
  prefix(recv_counts_, recv_displs_);
  in_.resize(total_of(recv_counts_));
  alltoallv_bytes(out_, send_counts_, send_displs_, in_, recv_counts_, recv_displs_, inter_,
                  "point results");
  for (int r = 0; r < remote_size_; ++r)
    if (static_cast<std::size_t>(recv_counts_[r]) != routed_[r].size() * result_bytes_)
      throw SolverError(
          fmt::format("point exchange: partner rank {} returned {} bytes of results for {} records "
                      "of {} bytes: the two sides called different exchanges (their order must match)",
                      r, recv_counts_[r], routed_[r].size(), result_bytes_));
  // Owner copies first, so that ghost copies combine into a defined value.
  for (int r = 0; r < remote_size_; ++r) {
    const std::byte* in = in_.data() + recv_displs_[r];
    for (std::uint32_t tagged : routed_[r]) {
      if (!(tagged & 0x80000000u))
        std::memcpy(results.data() + tagged * result_bytes_, in, result_bytes_);
      in += result_bytes_;
    }
  }
  for (int r = 0; r < remote_size_; ++r) {
    const std::byte* in = in_.data() + recv_displs_[r];
    for (std::uint32_t tagged : routed_[r]) {
      if ((tagged & 0x80000000u) && combine)
        combine(results.data() + (tagged & 0x7fffffffu) * result_bytes_, in);
      in += result_bytes_;
    }
  }
  trace().bytes_received += in_.size();
  ++trace().exchanges;
}

}  // namespace coflow::coupler
