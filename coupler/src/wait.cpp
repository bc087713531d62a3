#include "coflow/wait.hpp"

#include <thread>

#include <fmt/format.h>

#include "coflow/trace.hpp"

namespace coflow::coupler {

namespace {
double g_timeout = 300.0;

// Spin briefly (low latency for the common case), then back off to sleeping so
// that an oversubscribed core is left to the rank we wait for.
template <class Test>
void poll(Test test, const std::string& what, double* counter = nullptr) {
  const double start = now();
  Timer t(counter ? *counter : trace().wait_s);
  long spins = 0;
  while (!test()) {
    if (++spins > 2000) std::this_thread::sleep_for(std::chrono::microseconds(spins > 20000 ? 500 : 20));
    if ((spins & 63) == 0 && now() - start > g_timeout)
      throw TimeoutError(fmt::format(
          "waited {:.0f} s for {} without an answer (coupling.timeout); a partner component is "
          "stuck or gone",
          g_timeout, what));
  }
}
}  // namespace

void set_timeout(double seconds) { g_timeout = seconds; }
double timeout() { return g_timeout; }

void wait_all(std::span<MPI_Request> requests, const std::string& what, double* counter) {
  if (requests.empty()) return;
  poll(
      [&] {
        int done = 0;
        MPI_Testall(static_cast<int>(requests.size()), requests.data(), &done, MPI_STATUSES_IGNORE);
        return done != 0;
      },
      what, counter);
}

MPI_Status wait_probe(int source, int tag, MPI_Comm comm, const std::string& what) {
  MPI_Status st{};
  poll(
      [&] {
        int flag = 0;
        MPI_Iprobe(source, tag, comm, &flag, &st);
        return flag != 0;
      },
      what);
  return st;
}

}  // namespace coflow::coupler
