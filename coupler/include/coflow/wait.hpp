// Every blocking wait in coflow goes through here, so none can last forever:
// after `timeout` seconds without completion the wait throws, and the caller's
// component aborts the whole run with the reason.
#pragma once

#include <mpi.h>

#include <span>
#include <stdexcept>
#include <string>

namespace coflow::coupler {

class TimeoutError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

void set_timeout(double seconds);
double timeout();

// Wait for all requests; the time is added to `counter` (default: the trace's
// coupling wait time).
void wait_all(std::span<MPI_Request> requests, const std::string& what, double* counter = nullptr);
inline void wait_one(MPI_Request& r, const std::string& what) { wait_all({&r, 1}, what); }
// Probe for a message; returns its status.
MPI_Status wait_probe(int source, int tag, MPI_Comm comm, const std::string& what);

}  // namespace coflow::coupler
