// M x N exchange of cell fields and of point records between two components
// over an intercommunicator.
//
// Both sides know both decompositions (they read the same configuration), so
// the communication map is computed locally, once, from block intersections.
// After setup only point-to-point messages flow, into preallocated buffers.
#pragma once

#include <mpi.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "coflow/decomposition.hpp"
#include "coflow/mpi_count.hpp"

namespace coflow::coupler {

// consistent: values are copied (velocity); the receiver's ghost layer is filled too.
// conservative: sums are preserved (momentum sources); the sender's ghost layer
// is included and added into the owning receiver cells.
enum class Transfer { consistent, conservative };

struct FieldSpec {
  std::string name;
  int components = 1;
  Transfer transfer = Transfer::consistent;
  int ghost = 0;  // width of the ghost layer of the local arrays, on both sides
};

// Local arrays cover the block grown by the ghost width; x runs fastest and the
// components of a cell are contiguous: ((k * ny + j) * nx + i) * components + c.
class FieldExchange {
 public:
  enum class Role { sender, receiver };

  FieldExchange(MPI_Comm inter, Role role, const Decomposition& mine, int my_rank,
                const Decomposition& remote, FieldSpec spec, int tag);
  ~FieldExchange();
  FieldExchange(const FieldExchange&) = delete;
  FieldExchange& operator=(const FieldExchange&) = delete;

  const FieldSpec& spec() const { return spec_; }
  // The local array's box (global, unwrapped cell coordinates).
  const Box& local_box() const { return local_box_; }
  std::size_t local_size() const { return static_cast<std::size_t>(local_box_.volume()) * spec_.components; }
  long local_index(const Index3& global) const;  // cell index in the local array

  // Dense: every cell of the map. send() returns at once; the messages complete
  // in the background, before the next send() or in flush(). Messages that are
  // one contiguous run of cells are sent straight from `local` (no copy), so
  // `local` must stay unchanged until then, as with MPI_Isend.
  void send(std::span<const double> local);
  // Consistent: overwrites the cells received (owned + ghost). Conservative:
  // zeroes the owned cells, then adds every contribution to them.
  void receive(std::span<double> local);

  // Sparse: only listed cells travel. `cells` are global (possibly unwrapped)
  // indices within the sender's local box; `values` holds `components` per cell.
  void send_sparse(std::span<const Index3> cells, std::span<const double> values);
  // The received cells (as local-array cell indices) and their values, in
  // place of what the two vectors held.
  void receive_sparse(std::vector<long>& cells, std::vector<double>& values);

  // Replies to a sparse message, without cell indices (like PointExchange's
  // results): the receiver answers `components` values per cell of its last
  // receive_sparse(), in the order it got them (returns at once; `results`
  // is copied), and the sender gets them back per cell of its last
  // send_sparse(), in its order (zeros for a cell that went to no rank).
  // Each cell must reach one rank at most: conservative, or consistent
  // without a ghost layer.
  void reply_sparse(std::span<const double> results, int components);
  // The same without copying `results`, which comes back holding another buffer.
  void reply_sparse(std::vector<double>&& results, int components);
  void receive_replies(std::span<double> results, int components);

  void flush();  // complete outstanding sends
  std::size_t peers() const { return peers_.size(); }

 private:
  struct Peer {
    int rank = 0;
    Box remote_local;         // the receiving side's local box (its block grown by the ghost layer)
    std::vector<long> cells;  // local cell indices in message order
    long contiguous = -1;     // first cell when `cells` is one contiguous run (zero-copy)
    std::vector<double> buffer;
    std::vector<std::byte> sparse;  // send_sparse: grows only; its first sparse_used bytes are the message
    std::size_t sparse_used = 0;
    std::vector<std::int32_t> sent;  // send_sparse: the input cells sent to this rank, in message order
    std::size_t sent_count = 0;      // (its first sent_count entries; it only grows)
    std::size_t received = 0;        // receive_sparse: the cells that came from this rank
    std::vector<double> reply;       // receive_replies: the replies received
    MPI_Request request = MPI_REQUEST_NULL;
  };
  // send_sparse, consistent: where an owned cell goes. A cell in `from` goes
  // to peer `peer` as its image shifted by `shift` (the peer's block grown
  // by the ghost layer, clipped, shifted back into this side's frame,
  // intersected with the owned block); in the order peer, then image shift.
  struct Route {
    int peer;
    Index3 shift;
    Box from;
  };
  void check_replies(const char* call, int components) const;
  void start_replies(std::size_t values, int components);
  void send_replies(int components);
  void pack_sparse(std::span<const Index3> cells, std::span<const double> values);
  void unpack_sparse(const Peer& p, long* cells, double* values) const;
  void build_routes();
  void append_sparse(Peer& p, const Index3& cell, std::size_t n, std::span<const double> values);
  // Where pack_routes() writes a peer's next record.
  struct Cursor {
    std::byte* out = nullptr;      // the next record
    std::byte* end = nullptr;      // the end of the room for whole records
    std::int32_t* sent = nullptr;  // the next entry of Peer::sent
    Index3 shift_lo{}, extent{};   // minus the peer's local box's lower corner; its extents
  };
  bool pack_routes(std::span<const Index3> cells, std::span<const double> values);
  void reserve_records(std::size_t i, std::size_t records, std::size_t rec);
  Cursor grow_records(std::size_t i, std::size_t rec);
  void build(const Decomposition& mine, int my_rank, const Decomposition& remote);

  MPI_Comm inter_;
  Role role_;
  FieldSpec spec_;
  int tag_;
  Box local_box_;
  Box owned_;
  Decomposition mine_;
  Decomposition remote_;
  std::vector<Peer> peers_;
  std::vector<int> peer_of_;  // remote rank -> index in peers_, or -1
  std::vector<MPI_Request> requests_;
  std::vector<MPI_Request> sparse_requests_;
  std::vector<MPI_Request> reply_requests_;
  std::size_t sparse_sent_ = 0;  // cells given to the last send_sparse()
  std::vector<Route> routes_;
  bool routes_built_ = false;
  std::vector<double> reply_out_;  // the replies in flight (reply_sparse)
  bool routes_disjoint_ = false;   // no two routes' `from` boxes overlap: a cell takes one route at most
  std::vector<Cursor> cursors_;    // pack_routes(): one per peer
  bool sends_pending_ = false;
};

// Routes fixed-size records to the ranks of a remote decomposition that own
// their position (and, with a ghost width, to ranks whose ghost layer holds
// them), and brings per-record results back to the origin in the original order.
class PointExchange {
 public:
  enum class Role { origin, destination };

  // `lower` and `spacing` map positions to cells of the destination's grid.
  PointExchange(MPI_Comm inter, Role role, const Decomposition& destination,
                std::array<double, 3> lower, std::array<double, 3> spacing,
                std::size_t record_bytes, std::size_t result_bytes, int tag, int ghost = 0);

  // origin: send one record per position.
  void send(std::span<const std::byte> records, std::span<const std::array<double, 3>> positions);
  // destination: all records addressed to this rank, grouped by origin rank in
  // rank order, each group in the origin's order. `owned[i]` is 1 when this
  // rank owns record i's position, 0 for a ghost copy.
  void receive(std::vector<std::byte>& records, std::vector<std::uint8_t>& owned);
  // destination: one result per received record, same order.
  void send_results(std::span<const std::byte> results);
  // origin: results in the order of send(). A record that went to several
  // ranks gets `combine(into, from)` for each extra copy (e.g. summing forces).
  void receive_results(std::span<std::byte> results,
                       void (*combine)(std::byte* into, const std::byte* from) = nullptr);

 private:
  MPI_Comm inter_;
  Role role_;
  Decomposition dest_;
  std::array<double, 3> lower_, spacing_;
  std::size_t record_bytes_, result_bytes_;
  int tag_, ghost_;
  int remote_size_ = 0;
  // origin bookkeeping, reused across calls
  std::vector<int> send_counts_, recv_counts_, send_displs_, recv_displs_;
  std::vector<std::vector<std::uint32_t>> routed_;  // per destination: record indices
  std::vector<std::byte> out_, in_;
  std::size_t nrecords_ = 0;
};

}  // namespace coflow::coupler
