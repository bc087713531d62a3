// Exchange tracing: time in exchange (packing, posting, copying), time spent
// waiting for partners, and bytes moved, per component.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

namespace coflow::coupler {

struct Trace {
  double exchange_s = 0.0;  // inside exchange calls, not waiting
  double wait_s = 0.0;      // blocked on a partner
  double io_s = 0.0;        // snapshots, series, checkpoints
  double halo_s = 0.0;      // a solver's own halo exchange (part of compute, not coupling)
  std::uint64_t bytes_sent = 0;
  std::uint64_t bytes_received = 0;
  std::uint64_t exchanges = 0;
  std::uint64_t steps = 0;  // solver steps (component-defined)
};

Trace& trace();  // this process's trace

inline double now() {
  using namespace std::chrono;
  return duration<double>(steady_clock::now().time_since_epoch()).count();
}

// Adds the elapsed time to a counter when it leaves scope.
class Timer {
 public:
  explicit Timer(double& into) : into_(into), start_(now()) {}
  ~Timer() { into_ += now() - start_; }
  Timer(const Timer&) = delete;
  Timer& operator=(const Timer&) = delete;

 private:
  double& into_;
  double start_;
};

}  // namespace coflow::coupler
