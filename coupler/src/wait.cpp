#include "coflow/wait.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <thread>
#include <unordered_map>

#include "coflow/trace.hpp"

namespace coflow::coupler {

namespace {
double g_timeout = 300.0;

// How long each kind of wait (by its description) lasted the last three times.
// Coupled components wait for each other in a fixed rhythm, one window after
// another; a rank that knows it will wait about as long as before sleeps
// through most of it instead of polling, and leaves the core to the rank it
// waits for (or, under ctest -j, to another run).
struct History {
  double last[3] = {0.0, 0.0, 0.0};
  int count = 0, next = 0;
  // The shortest of the last three: one long wait (an output window) does not
  // delay the next ones. Waits under a millisecond (a solver's ghost
  // exchanges, whose levels share one description) are not dozed through.
  double expected() const {
    const double shortest = count < 3 ? 0.0 : std::min({last[0], last[1], last[2]});
    return shortest > 1e-3 ? shortest : 0.0;
  }
  void add(double seconds) {
    last[next] = seconds;
    next = (next + 1) % 3;
    count = std::min(count + 1, 3);
  }
};
std::unordered_map<std::string, History> g_history;

// Sleep through the expected wait less a margin of a tenth of it or 1 ms,
// whichever is more, testing every 5 ms at most; then spin (low latency: a
// waiting rank is often next on the critical path) until the same margin past
// it, and back off to short sleeps after that, so that an oversubscribed core
// is left to the rank we wait for. A wait with no history spins 2000 tests
// before it backs off. Each test is a system call (Open MPI yields the core in
// every progress call when oversubscribed): spinning through the last fifth
// of a 20 ms rhythm, as the waits did with a margin of a fifth, kept a waiting
// rank a fifth busy.
template <class Test>
void poll(Test test, const std::string& what, double* counter = nullptr) {
  const double start = now();
  Timer t(counter ? *counter : trace().wait_s);
  History& history = g_history[what];
  const double expected = history.expected();
  const double margin = std::max(0.1 * expected, 1e-3);
  const double doze_until = start + expected - margin, spin_until = start + expected + margin;
  long spins = 0;
  while (!test()) {
    const double time = now();
    if (time < doze_until) {
      std::this_thread::sleep_for(std::chrono::duration<double>(std::min(doze_until - time, 5e-3)));
      continue;
    }
    ++spins;
    if (expected > 0.0 ? time > spin_until : spins > 2000)
      std::this_thread::sleep_for(std::chrono::microseconds(spins > 20000 ? 500 : 20));
    if ((spins & 63) == 0 && time - start > g_timeout)
      throw TimeoutError(fmt::format(
          "waited {:.0f} s for {} without an answer (coupling.timeout); a partner component is "
          "stuck or gone",
          g_timeout, what));
  }
  history.add(now() - start);
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
