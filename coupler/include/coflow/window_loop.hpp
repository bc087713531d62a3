// The one window loop every component runs (docs/protocol.md §4). A component
// hands run_windows() an object with the parts of a window; the loop calls
//
//   start(w0)                      once, after a restart from window w0 or w0 = 0
//   for w = w0 + 1 .. windows:
//     before_step(w)               exchanges the step needs (send states, receive loads)
//     step(w)                      advance the solver by one window
//     after_step(w)                exchanges of what the step produced
//     output(w)                    series, snapshots and events due at w
//     checkpoint of save(dir)      when one is due
//     window_done(w)               progress, and the check of the run's state
//   finish()                       complete what is still in flight
//
// What goes before and after the step is the coupling scheme's business: a
// component with no partner exchanges nothing.
#pragma once

#include <string>

#include "coflow/session.hpp"

namespace coflow::coupler {

class WindowParts {
 public:
  virtual ~WindowParts() = default;
  virtual void start(long w0) { (void)w0; }
  virtual void before_step(long w) { (void)w; }
  virtual void step(long w) = 0;
  virtual void after_step(long w) { (void)w; }
  virtual void output(long w) = 0;  // w = 0: the initial state
  virtual void save(const std::string& dir) = 0;
  virtual void finish() {}
};

inline void run_windows(Session& s, WindowParts& parts) {
  const long w0 = s.restart_window();
  parts.start(w0);
  for (long w = w0 + 1; w <= s.windows(); ++w) {
    parts.before_step(w);
    parts.step(w);
    parts.after_step(w);
    parts.output(w);
    s.checkpoint(w, [&](const std::string& dir) { parts.save(dir); });
    s.window_done(w);
  }
  parts.finish();
}

}  // namespace coflow::coupler
