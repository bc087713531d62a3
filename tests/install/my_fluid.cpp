// A user's own fluid component, built out of tree: it follows the protocol of
// docs/protocol.md (negotiate the window, loop over windows, report progress)
// and publishes a final scalar that the test reads back from summary.json. It
// links libcoflow alone (coflow::coupler): no solver, no schema of coflow's own
// components.
#include "coflow/session.hpp"

int main(int argc, char** argv) {
  return coflow::coupler::run_component("fluid", argc, argv, [](coflow::coupler::Session& s) {
    s.negotiate_window(0.25);
    double sum = 0.0;
    for (long w = 1; w <= s.windows(); ++w) {
      sum += w;
      s.window_done(w);
    }
    s.set_final("my_fluid.window_sum", sum);
  });
}
