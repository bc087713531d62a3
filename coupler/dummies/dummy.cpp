// Dummy components: tiny stand-ins for the fluid, immersed and particle solvers.
//
// They follow the same protocol as the real components (docs/protocol.md), with
// data whose every value is known, and check what they receive:
//  - particles -> immersed: random point records; the immersed side answers one
//    result per record, and particles check that each comes back to its origin,
//    in order, once per rank that holds the point (owner + ghost copies);
//  - immersed -> fluid: a conservative momentum source filled over the sender's
//    block *and* ghost layer; the fluid checks every owned cell and the global sum;
//  - fluid -> immersed: the consistent field u = (sin x, y^2, z); the immersed side
//    checks every owned and ghost cell bit for bit.
// Each field travels dense and sparse, with ghost widths 0 and 2.
//
// Built three times (COFLOW_DUMMY = fluid | immersed | particles). This file is
// also the template for writing a component of your own: see docs/protocol.md.
#include <fmt/format.h>
#include <signal.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <random>
#include <thread>

#include "coflow/discovery.hpp"
#include "coflow/exchange.hpp"
#include "coflow/log.hpp"
#include "coflow/session.hpp"
#include "coflow/window_loop.hpp"

namespace {

using namespace coflow;
using coupler::Box;
using coupler::Decomposition;
using coupler::FieldExchange;
using coupler::Index3;
using coupler::PointExchange;

struct DummyParams {
  double step = 0.1;       // fluid: the step it offers as the coupling window
  int points = 1000;       // particles: point records per rank per window
  int fail_at_window = 0;  // throw at this window (0: never)
  int kill_at_window = 0;  // SIGKILL itself at this window
  int hang_at_window = 0;  // stop answering at this window
  int nan_at_window = 0;   // particles: send a position that is not finite at this window
  int fail_rank = 0;       // which rank of the component misbehaves
  void visit(config::Visitor& v) {
    v("step", step, "fluid: natural step, s", config::positive());
    v("points", points, "particles: point records per rank and window", config::non_negative());
    v("fail_at_window", fail_at_window, "throw an error at this window (0: never)", config::non_negative());
    v("kill_at_window", kill_at_window, "SIGKILL one rank at this window (0: never)", config::non_negative());
    v("hang_at_window", hang_at_window, "stop answering at this window (0: never)", config::non_negative());
    v("nan_at_window", nan_at_window,
      "particles: send a point whose position is NaN at this window (0: never)", config::non_negative());
    v("fail_rank", fail_rank, "the rank that misbehaves", config::non_negative());
  }
};

struct PointRecord {
  std::int64_t id;
  double x[3];
};
struct PointResult {
  std::int64_t id;
  double copies;
  double value;
};

void add_result(std::byte* into, const std::byte* from) {
  PointResult a, b;
  std::memcpy(&a, into, sizeof a);
  std::memcpy(&b, from, sizeof b);
  a.copies += b.copies;
  a.value += b.value;
  std::memcpy(into, &a, sizeof a);
}

double point_value(const PointRecord& r) {
  return r.x[0] + 2 * r.x[1] + 3 * r.x[2] + 1e-3 * r.id;
}

// The fluid's velocity field and the immersed side's source, per global cell.
std::array<double, 3> velocity_of(const config::Config& cfg, const Index3& c) {
  const auto h = cfg.domain.spacing();
  const double x = cfg.domain.lower[0] + (c[0] + 0.5) * h[0];
  const double y = cfg.domain.lower[1] + (c[1] + 0.5) * h[1];
  const double z = cfg.domain.lower[2] + (c[2] + 0.5) * h[2];
  return {std::sin(x), y * y, z};
}
std::array<double, 3> source_of(const Index3& c, long w) {
  const double v = 1.0 + 1e-3 * (c[0] + 7 * c[1] + 31 * c[2]) + 0.01 * w;
  return {v, -2 * v, 0.5 * v};
}
bool sparse_cell(const Index3& c) {
  return ((c[0] + c[1] + c[2]) % 3 + 3) % 3 == 0;
}

template <class F>
void for_cells(const Box& b, F&& f) {
  for (long k = b.lo[2]; k < b.hi[2]; ++k)
    for (long j = b.lo[1]; j < b.hi[1]; ++j)
      for (long i = b.lo[0]; i < b.hi[0]; ++i) f(Index3{i, j, k});
}

void misbehave(const coupler::Session& s, const DummyParams& p, long w) {
  if (s.rank() != p.fail_rank) return;
  if (p.fail_at_window == w)
    throw std::runtime_error(fmt::format("dummy {} failing on purpose at window {}", s.component(), w));
  if (p.kill_at_window == w) raise(SIGKILL);
  if (p.hang_at_window == w) {
    coflow::log::warn("dummy hanging on purpose at window {}", w);
    for (;;) std::this_thread::sleep_for(std::chrono::seconds(1));
  }
}

// The four variants of each field exchange.
struct Variant {
  bool sparse;
  int ghost;
};
const Variant kVariants[] = {{false, 0}, {false, 2}, {true, 0}, {true, 2}};

constexpr int kTagVelocity = 100, kTagSource = 200, kTagPoints = 300;

// The four variants of the velocity (fluid -> immersed, consistent) and source
// (immersed -> fluid, conservative) exchanges with `partner`, from either side.
struct FieldExchanges {
  std::vector<std::unique_ptr<FieldExchange>> velocity, source;
};

FieldExchanges make_exchanges(coupler::Session& s, const std::string& partner) {
  FieldExchanges e;
  if (!s.has_partner(partner)) return e;
  const bool fluid = s.component() == "fluid";
  const Decomposition mine = s.decomposition();
  const Decomposition other = s.decomposition_of(partner, s.partner_ranks(partner));
  const auto sender = FieldExchange::Role::sender, receiver = FieldExchange::Role::receiver;
  for (int v = 0; v < 4; ++v) {
    e.velocity.push_back(std::make_unique<FieldExchange>(
        s.partner(partner), fluid ? sender : receiver, mine, s.rank(), other,
        coupler::FieldSpec{"velocity", 3, coupler::Transfer::consistent, kVariants[v].ghost}, kTagVelocity + 10 * v));
    e.source.push_back(std::make_unique<FieldExchange>(
        s.partner(partner), fluid ? receiver : sender, mine, s.rank(), other,
        coupler::FieldSpec{"source", 3, coupler::Transfer::conservative, kVariants[v].ghost}, kTagSource + 10 * v));
  }
  return e;
}

// ------------------------------------------------------------------ fluid ---

// Each window the fluid dummy receives the immersed side's source and checks it
// cell by cell, and sends its velocity; the order is the coupling scheme's.
class FluidDummy final : public coupler::WindowParts {
 public:
  FluidDummy(coupler::Session& s, const DummyParams& p)
      : s_(s), p_(p), owned_(s.decomposition().block(s.rank())), ex_(make_exchanges(s, "immersed")) {}

  void before_step(long w) override {
    misbehave(s_, p_, w);
    coupler::trace().steps = w;
    if (!s_.has_partner("immersed")) return;
    // serial-explicit: the fluid steps on this window's source, then sends its
    // velocity; parallel-explicit: it sends first, so particles and fluid work
    // at the same time on the previous window's data.
    if (s_.config().coupling.scheme == config::Scheme::parallel_explicit) {
      send_velocity();
      receive_source(w);
    } else {
      receive_source(w);
      send_velocity();
    }
    ++checked_;
  }
  void step(long) override {}
  void output(long) override {}
  void save(const std::string&) override {}  // a component with no state still takes part
  void finish() override {
    for (int v = 0; v < 4; ++v)
      if (s_.has_partner("immersed") && kVariants[v].sparse && kVariants[v].ghost == 0 && checked_ > 0)
        check_replies(v);  // to the last window's velocity
    for (auto& e : ex_.velocity) e->flush();
    for (auto& e : ex_.source) e->flush();  // the replies
    s_.set_final("dummy.checked_windows", static_cast<double>(checked_));
  }

 private:
  void receive_source(long w);
  void check_source(int v, long w);
  void send_velocity();
  void check_replies(int v);

  coupler::Session& s_;
  const DummyParams& p_;
  Box owned_;
  FieldExchanges ex_;
  std::vector<double> local_;
  std::vector<std::vector<double>> outgoing_ = std::vector<std::vector<double>>(4);  // untouched until the next send
  std::vector<Index3> cells_;
  std::vector<double> values_, got_values_;
  std::vector<long> got_cells_;
  std::vector<double> sent_values_, replies_;  // the ghost-free sparse velocity, and its replies
  long checked_ = 0;  // windows whose received source was checked
};

void FluidDummy::receive_source(long w) {
  for (int v = 0; v < 4; ++v) {
    auto& ex = *ex_.source[v];
    local_.assign(ex.local_size(), 0.0);
    if (kVariants[v].sparse) {
      got_cells_.clear();
      got_values_.clear();
      ex.receive_sparse(got_cells_, got_values_);
      for (std::size_t n = 0; n < got_cells_.size(); ++n)
        for (int c = 0; c < 3; ++c) local_[got_cells_[n] * 3 + c] += got_values_[n * 3 + c];
      // The sender checks that each cell's reply is its own value, negated.
      for (double& x : got_values_) x = -x;
      ex.reply_sparse(got_values_, 3);
    } else {
      ex.receive(local_);
    }
    check_source(v, w);
  }
}

// Each owned cell must hold the sum of the source over every (sender rank,
// periodic image) that covers it, and the totals must agree.
void FluidDummy::check_source(int v, long w) {
  const auto& ex = *ex_.source[v];
  const Decomposition other = s_.decomposition_of("immersed", s_.partner_ranks("immersed"));
  const Index3 g = other.ghost(kVariants[v].ghost);
  double sum = 0.0, expected_sum = 0.0;
  for_cells(owned_, [&](const Index3& c) {
    int cover = 0;
    for (int r = 0; r < other.ranks(); ++r) {
      const Box src = other.clip(other.block(r).grown(g));
      for (const auto& sh : other.image_shifts())
        if (src.contains({c[0] + sh[0], c[1] + sh[1], c[2] + sh[2]})) ++cover;
    }
    if (kVariants[v].sparse && !sparse_cell(c)) cover = 0;
    const auto src = source_of(c, w);
    const double* got = local_.data() + ex.local_index(c) * 3;
    for (int k = 0; k < 3; ++k) {
      const double want = cover * src[k];
      if (!(std::abs(got[k] - want) <= 1e-12 * std::abs(want) + 1e-300))  // NaN fails
        throw std::runtime_error(fmt::format("fluid: source at ({},{},{}) comp {} is {} not {} (variant {})", c[0],
                                             c[1], c[2], k, got[k], want, v));
      sum += got[k];
      expected_sum += want;
    }
  });
  double both[2] = {sum, expected_sum}, total[2];
  MPI_Allreduce(both, total, 2, MPI_DOUBLE, MPI_SUM, s_.comm());
  if (!(std::abs(total[0] - total[1]) <= 1e-12 * std::abs(total[1])))
    throw std::runtime_error(fmt::format("fluid: source total {} != {}", total[0], total[1]));
}

void FluidDummy::send_velocity() {
  const auto& cfg = s_.config();
  for (int v = 0; v < 4; ++v) {
    auto& ex = *ex_.velocity[v];
    ex.flush();  // the previous window's messages may still read outgoing_[v]
    auto& out = outgoing_[v];
    out.assign(ex.local_size(), 0.0);
    for_cells(owned_, [&](const Index3& c) {
      const auto u = velocity_of(cfg, c);
      for (int k = 0; k < 3; ++k) out[ex.local_index(c) * 3 + k] = u[k];
    });
    if (!kVariants[v].sparse) {
      ex.send(out);
      continue;
    }
    if (kVariants[v].ghost == 0 && checked_ > 0) check_replies(v);  // to the last window's
    cells_.clear();
    values_.clear();
    for_cells(owned_, [&](const Index3& c) {
      if (!sparse_cell(c)) return;
      cells_.push_back(c);
      const auto u = velocity_of(cfg, c);
      values_.insert(values_.end(), u.begin(), u.end());
    });
    ex.send_sparse(cells_, values_);
    if (kVariants[v].ghost == 0) sent_values_ = values_;
  }
}

// The immersed side answers each sparse velocity value of the ghost-free
// variant with its negative: every owned cell reaches one rank.
void FluidDummy::check_replies(int v) {
  replies_.assign(sent_values_.size(), std::nan(""));
  ex_.velocity[v]->receive_replies(replies_, 3);
  for (std::size_t n = 0; n < replies_.size(); ++n)
    if (!(replies_[n] == -sent_values_[n]))
      throw std::runtime_error(fmt::format("fluid: velocity reply {} is {} not {} (variant {})", n,
                                           replies_[n], -sent_values_[n], v));
}

void run_fluid(coupler::Session& s, const DummyParams& p) {
  s.negotiate_window(p.step);
  FluidDummy windows(s, p);
  coupler::run_windows(s, windows);
}

// --------------------------------------------------------------- immersed ---

// Each window the immersed dummy answers the particles' points, sends its
// source to the fluid and checks the fluid's velocity in every cell it holds.
class ImmersedDummy final : public coupler::WindowParts {
 public:
  ImmersedDummy(coupler::Session& s, const DummyParams& p) : s_(s), p_(p), mine_(s.decomposition()) {
    const auto& cfg = s.config();
    if (s.has_partner("particles"))
      points_ = std::make_unique<PointExchange>(s.partner("particles"), PointExchange::Role::destination, mine_,
                                                cfg.domain.lower, cfg.domain.spacing(), sizeof(PointRecord),
                                                sizeof(PointResult), kTagPoints, 2);
    ex_ = make_exchanges(s, "fluid");
  }

  void before_step(long w) override {
    misbehave(s_, p_, w);
    if (points_) answer_points();
    if (s_.config().coupling.scheme == config::Scheme::parallel_explicit) {
      receive_velocity();
      send_source(w);
    } else {
      send_source(w);
      receive_velocity();
    }
  }
  void step(long) override {}
  void output(long) override {}
  void save(const std::string&) override {}
  void finish() override {
    for (auto& e : ex_.source) e->flush();
  }

 private:
  void answer_points();
  void send_source(long w);
  void receive_velocity();
  void check_velocity(int v, const Box& box);
  void check_replies(int v);

  coupler::Session& s_;
  const DummyParams& p_;
  Decomposition mine_;
  std::unique_ptr<PointExchange> points_;
  FieldExchanges ex_;
  std::vector<std::byte> records_, results_;
  std::vector<std::uint8_t> owned_flags_;
  std::vector<double> local_, values_, got_values_;
  std::vector<Index3> cells_;
  std::vector<long> got_cells_;
  std::vector<Index3> sent_cells_[4];  // the last sparse sources, for their replies
  std::vector<double> sent_values_[4], replies_;
};

void ImmersedDummy::answer_points() {
  points_->receive(records_, owned_flags_);
  const std::size_t n = owned_flags_.size();
  results_.resize(n * sizeof(PointResult));
  for (std::size_t i = 0; i < n; ++i) {
    PointRecord r;
    std::memcpy(&r, records_.data() + i * sizeof r, sizeof r);
    const PointResult out{r.id, 1.0, point_value(r)};
    std::memcpy(results_.data() + i * sizeof out, &out, sizeof out);
  }
  points_->send_results(results_);
}

void ImmersedDummy::send_source(long w) {
  for (int v = 0; v < 4 && !ex_.source.empty(); ++v) {
    auto& ex = *ex_.source[v];
    const Box box = mine_.clip(ex.local_box());
    local_.assign(ex.local_size(), 0.0);
    for_cells(box, [&](const Index3& c) {
      const auto src = source_of(mine_.wrap(c), w);
      for (int k = 0; k < 3; ++k) local_[ex.local_index(c) * 3 + k] = src[k];
    });
    if (!kVariants[v].sparse) {
      ex.send(local_);
      continue;
    }
    cells_.clear();
    values_.clear();
    for_cells(box, [&](const Index3& c) {
      if (!sparse_cell(mine_.wrap(c))) return;
      cells_.push_back(c);
      const auto src = source_of(mine_.wrap(c), w);
      values_.insert(values_.end(), src.begin(), src.end());
    });
    ex.send_sparse(cells_, values_);
    sent_cells_[v] = cells_;
    sent_values_[v] = values_;
  }
  for (int v = 0; v < 4 && !ex_.source.empty(); ++v)
    if (kVariants[v].sparse) check_replies(v);
}

// The fluid replies to each sparse source cell with its value negated (every
// cell sent lies in the domain, so each reaches one rank).
void ImmersedDummy::check_replies(int v) {
  const auto& cells = sent_cells_[v];
  const auto& values = sent_values_[v];
  replies_.assign(values.size(), std::nan(""));
  ex_.source[v]->receive_replies(replies_, 3);
  for (std::size_t n = 0; n < cells.size(); ++n) {
    const Index3& c = cells[n];
    for (int k = 0; k < 3; ++k) {
      const double expected = -values[3 * n + k];
      if (!(replies_[3 * n + k] == expected))
        throw std::runtime_error(
            fmt::format("immersed: reply for ({},{},{}) comp {} is {} not {} (variant {})", c[0], c[1], c[2],
                        k, replies_[3 * n + k], expected, v));
    }
  }
}

void ImmersedDummy::receive_velocity() {
  for (int v = 0; v < 4 && !ex_.velocity.empty(); ++v) {
    auto& ex = *ex_.velocity[v];
    const Box box = mine_.clip(ex.local_box());
    local_.assign(ex.local_size(), std::nan(""));
    if (kVariants[v].sparse) {
      got_cells_.clear();
      got_values_.clear();
      ex.receive_sparse(got_cells_, got_values_);
      for (std::size_t n = 0; n < got_cells_.size(); ++n)
        for (int c = 0; c < 3; ++c) local_[got_cells_[n] * 3 + c] = got_values_[n * 3 + c];
      long expected_count = 0;
      for_cells(box, [&](const Index3& c) { expected_count += sparse_cell(mine_.wrap(c)); });
      if (static_cast<long>(got_cells_.size()) != expected_count)
        throw std::runtime_error(
            fmt::format("immersed: {} sparse cells received, {} expected", got_cells_.size(), expected_count));
      // A consistent exchange without ghosts can be answered: each value, negated.
      if (kVariants[v].ghost == 0) {
        for (double& x : got_values_) x = -x;
        ex.reply_sparse(got_values_, 3);
      }
    } else {
      ex.receive(local_);
    }
    check_velocity(v, box);
  }
}

// Every cell of the clipped local box (owned + ghost) must hold the exact value
// of the wrapped cell.
void ImmersedDummy::check_velocity(int v, const Box& box) {
  const auto& ex = *ex_.velocity[v];
  for_cells(box, [&](const Index3& c) {
    if (kVariants[v].sparse && !sparse_cell(mine_.wrap(c))) return;
    const auto u = velocity_of(s_.config(), mine_.wrap(c));
    const double* got = local_.data() + ex.local_index(c) * 3;
    for (int k = 0; k < 3; ++k)
      if (got[k] != u[k])
        throw std::runtime_error(fmt::format("immersed: velocity at ({},{},{}) comp {} is {} not {} (variant {})",
                                             c[0], c[1], c[2], k, got[k], u[k], v));
  });
}

void run_immersed(coupler::Session& s, const DummyParams& p) {
  s.negotiate_window(0.0);
  ImmersedDummy windows(s, p);
  coupler::run_windows(s, windows);
}

// -------------------------------------------------------------- particles ---

void run_particles(coupler::Session& s, const DummyParams& p) {
  const auto& cfg = s.config();
  s.negotiate_window(0.0);
  if (!s.has_partner("immersed")) {
    for (long w = 1; w <= s.windows(); ++w) {
      misbehave(s, p, w);
      s.checkpoint(w, [](const std::string&) {});  // every component takes part
      s.window_done(w);
    }
    return;
  }
  const Decomposition dest = s.decomposition_of("immersed", s.partner_ranks("immersed"));
  const auto h = cfg.domain.spacing();
  PointExchange ex(s.partner("immersed"), PointExchange::Role::origin, dest, cfg.domain.lower, h,
                   sizeof(PointRecord), sizeof(PointResult), kTagPoints, 2);
  std::vector<std::byte> records(p.points * sizeof(PointRecord)), results(p.points * sizeof(PointResult));
  std::vector<std::array<double, 3>> pos(p.points);
  std::vector<PointRecord> recs(p.points);
  const Index3 g = dest.ghost(2);
  for (long w = 1; w <= s.windows(); ++w) {
    misbehave(s, p, w);
    std::mt19937_64 rng(cfg.run.seed + 7919 * s.rank() + 104729 * w);
    for (long i = 0; i < p.points; ++i) {
      PointRecord& r = recs[i];
      r.id = (static_cast<std::int64_t>(s.rank()) << 40) | i;
      for (int d = 0; d < 3; ++d) {
        std::uniform_real_distribution<double> u(cfg.domain.lower[d], cfg.domain.upper[d]);
        r.x[d] = pos[i][d] = u(rng);
      }
      std::memcpy(records.data() + i * sizeof r, &r, sizeof r);
    }
    if (p.nan_at_window == w && s.rank() == p.fail_rank && p.points > 0) pos[0][1] = std::nan("");
    ex.send(records, pos);
    ex.receive_results(results, add_result);
    for (long i = 0; i < p.points; ++i) {
      PointResult out;
      std::memcpy(&out, results.data() + i * sizeof out, sizeof out);
      // How many ranks hold this point: its owner, plus every other rank whose
      // block grown by the ghost width contains it (any periodic image).
      Index3 c{};
      for (int d = 0; d < 3; ++d)
        c[d] = std::clamp(static_cast<long>(std::floor((pos[i][d] - cfg.domain.lower[d]) / h[d])), 0L,
                          cfg.domain.cells[d] - 1L);
      const int owner = dest.owner(c);
      int copies = 1;
      for (int r = 0; r < dest.ranks(); ++r) {
        if (r == owner) continue;
        for (const auto& sh : dest.image_shifts())
          if (dest.block(r).grown(g).contains({c[0] + sh[0], c[1] + sh[1], c[2] + sh[2]})) {
            ++copies;
            break;
          }
      }
      if (out.id != recs[i].id || out.copies != copies ||
          !(std::abs(out.value - copies * point_value(recs[i])) <=
            1e-12 * std::abs(copies * point_value(recs[i]))))
        throw std::runtime_error(fmt::format(
            "particles: result {} came back wrong: id {} (want {}), copies {} (want {}), value {} (want {})",
            i, out.id, recs[i].id, out.copies, copies, out.value, copies * point_value(recs[i])));
    }
    coupler::trace().steps = w;
    s.checkpoint(w, [](const std::string&) {});
    s.window_done(w);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::string component = COFLOW_DUMMY;
  // tests/coupler/discovery.sh: a component built with another protocol version.
  if (const char* v = std::getenv("COFLOW_DUMMY_PROTOCOL"))
    coupler::announce_protocol_version(static_cast<std::uint32_t>(std::stoul(v)));
  return coupler::run_component(component, argc, argv, [&](coupler::Session& s) {
    DummyParams p;
    YAML::Node section = s.config().resolved[component]["dummy"];
    config::Reader r(section, s.config().file, component + ".dummy");
    p.visit(r);
    r.finish();
    r.check();
    if (component == "fluid") run_fluid(s, p);
    if (component == "immersed") run_immersed(s, p);
    if (component == "particles") run_particles(s, p);
  });
}
