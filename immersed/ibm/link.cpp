#include "immersed/ibm/link.hpp"

#include <cstdlib>

#include "coflow/mpi_count.hpp"
#include "coflow/protocol.hpp"
#include "coflow/trace.hpp"
#include "coflow/wait.hpp"

namespace coflow::ibm {

using coupler::trace;

// The count goes first: the payload's size, negative when it is the last.
void send_markers(MPI_Comm fluid, int rank, bool last, const std::vector<double>& packed) {
  const int root = rank == 0 ? MPI_ROOT : MPI_PROC_NULL;
  // (checked before anything is sent: more than an MPI int count is an error here, not a wrapped count)
  const long count = rank == 0 ? coupler::mpi_count(packed.size(), "ibm markers") : 0;
  long sent = last ? -count : count;
  MPI_Request r;
  {
    coupler::Timer t(trace().exchange_s);
    MPI_Ibcast(&sent, 1, MPI_LONG, root, fluid, &r);
  }
  coupler::wait_one(r, "ibm markers to the fluid");
  {
    coupler::Timer t(trace().exchange_s);
    MPI_Ibcast(const_cast<double*>(packed.data()), static_cast<int>(count), MPI_DOUBLE, root, fluid, &r);
  }
  coupler::wait_one(r, "ibm markers to the fluid");
  if (rank == 0) {
    trace().bytes_sent += static_cast<std::uint64_t>(count) * sizeof(double);
    ++trace().exchanges;
  }
}

bool receive_markers(MPI_Comm immersed, std::vector<double>& packed, bool& last) {
  long count = 0;
  MPI_Request r;
  MPI_Ibcast(&count, 1, MPI_LONG, 0, immersed, &r);
  coupler::wait_one(r, "ibm markers from immersed");
  last = count < 0;
  count = std::abs(count);
  if (count == 0) return false;
  packed.resize(static_cast<std::size_t>(count));
  MPI_Ibcast(packed.data(), static_cast<int>(count), MPI_DOUBLE, 0, immersed, &r);
  coupler::wait_one(r, "ibm markers from immersed");
  trace().bytes_received += static_cast<std::uint64_t>(count) * sizeof(double);
  ++trace().exchanges;
  return true;
}

void send_loads(MPI_Comm immersed, const std::vector<double>& values) {
  MPI_Request r;
  {
    coupler::Timer t(trace().exchange_s);
    MPI_Isend(values.data(), coupler::mpi_count(values.size(), "ibm body loads"), MPI_DOUBLE, 0,
              protocol::kTagBodyLoads, immersed, &r);
  }
  coupler::wait_one(r, "ibm loads to immersed");
  trace().bytes_sent += values.size() * sizeof(double);
  ++trace().exchanges;
}

void receive_loads(MPI_Comm fluid, std::vector<double>& values) {
  MPI_Request r;
  MPI_Irecv(values.data(), coupler::mpi_count(values.size(), "ibm body loads"), MPI_DOUBLE, 0,
            protocol::kTagBodyLoads, fluid, &r);
  coupler::wait_one(r, "ibm loads from the fluid");
  trace().bytes_received += values.size() * sizeof(double);
  ++trace().exchanges;
}

}  // namespace coflow::ibm
