// coflow: the launcher. Validates a configuration, composes the MPMD launch of
// the component executables, runs it without a shell, shows progress, and
// reports how the run ended.
#include <fcntl.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <string_view>
#include <thread>
#include <utility>

#include "coflow/catalog.hpp"
#include "coflow/output.hpp"
#include "coflow/rank_split.hpp"
#include "coflow/session.hpp"
#include "restart.hpp"

namespace fs = std::filesystem;
using coflow::config::Config;
using coflow::config::ConfigError;

namespace {

volatile sig_atomic_t g_child = 0;
volatile sig_atomic_t g_interrupted = 0;  // the signal the user sent (Ctrl-C: SIGINT)

// A hangup (the terminal or the ssh session closed) stops the run as SIGTERM
// does: mpirun takes SIGTERM to end its job.
void forward_signal(int sig) {
  g_interrupted = sig;
  if (g_child > 0) kill(g_child, sig == SIGHUP ? SIGTERM : sig);
}

std::string self_dir() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string(".") : p.parent_path().string();
}

// Quote for display only; nothing here is ever passed to a shell.
std::string quoted(const std::string& s) {
  if (!s.empty() && s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-./=:,+@%") == std::string::npos)
    return s;
  std::string o = "'";
  for (char c : s) o += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return o + "'";
}

std::string join_cmd(const std::vector<std::string>& argv) {
  std::string s;
  for (const auto& a : argv) s += (s.empty() ? "" : " ") + quoted(a);
  return s;
}

std::string find_in_path(const std::string& exe) {
  if (exe.find('/') != std::string::npos) return fs::exists(exe) ? exe : "";
  const char* path = std::getenv("PATH");
  std::stringstream ss(path ? path : "");
  for (std::string dir; std::getline(ss, dir, ':');) {
    const fs::path p = fs::path(dir) / exe;
    if (!dir.empty() && access(p.c_str(), X_OK) == 0) return p.string();
  }
  return "";
}

struct Launch {
  std::vector<std::string> components;  // in launch order
  std::vector<int> ranks;
  std::vector<std::string> exes;
  int total = 0;
  std::string bind = "auto";  // run.launch.bind
  std::vector<std::string> mpi_args;
  // Whether component i runs a user's own executable (--exe), not the one
  // built beside the launcher.
  bool own(std::size_t i) const { return exes[i] != self_dir() + "/coflow-" + components[i]; }
};

Launch plan(const Config& cfg, const std::map<std::string, std::string>& exe_override) {
  Launch l;
  const std::string bin = self_dir();
  for (const auto& c : coflow::config::component_order()) {
    if (!cfg.has(c)) continue;
    l.components.push_back(c);
    l.ranks.push_back(cfg.component(c).ranks);
    auto it = exe_override.find(c);
    l.exes.push_back(it != exe_override.end() ? fs::absolute(it->second).string() : bin + "/coflow-" + c);
    l.total += cfg.component(c).ranks;
  }
  l.bind = cfg.run.launch.bind;
  // Several runs on one node at once (ctest -j) pin their ranks to the same
  // cores: COFLOW_BIND=none in every test's environment (tests/CMakeLists.txt)
  // decides what auto means there.
  if (const char* b = std::getenv("COFLOW_BIND"); b && l.bind == "auto") {
    if (std::string(b) == "none" || std::string(b) == "core")
      l.bind = b;
    else
      std::fprintf(stderr, "coflow: COFLOW_BIND=%s ignored (none or core)\n", b);
  }
  l.mpi_args = cfg.run.launch.mpi_args;
  return l;
}

// The physical cores this process may run on: Open MPI gives one slot per
// core (not per hardware thread) of its cpuset, so a 2-core laptop with 4
// threads has 2 slots. Counted as the distinct (package, core) pairs of the
// CPUs in the affinity mask; where sysfs does not say, the CPUs themselves.
int physical_cores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0)
    return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::set<std::pair<long, long>> cores;
  for (int c = 0; c < CPU_SETSIZE; ++c) {
    if (!CPU_ISSET(c, &set)) continue;
    const std::string topo = fmt::format("/sys/devices/system/cpu/cpu{}/topology/", c);
    long package = -1, core = -1;
    std::ifstream(topo + "physical_package_id") >> package;
    std::ifstream(topo + "core_id") >> core;
    if (package < 0 || core < 0) return std::max(1, CPU_COUNT(&set));  // unknown: count the CPUs
    cores.insert({package, core});
  }
  return std::max(1, static_cast<int>(cores.size()));
}

std::vector<std::string> mpirun_argv(const Launch& l, const std::string& config_path, const std::string& restart) {
  std::vector<std::string> a{"mpirun"};
  if (const char* m = std::getenv("COFLOW_MPIRUN")) a[0] = m;
  const bool over = l.total > physical_cores();
  if (over) a.push_back("--oversubscribe");
  // Pinned, ranks that share a core stay apart from those on the other cores
  // (measured: quickstart, 4 ranks on 2 cores, 4.1-4.7 s pinned, 4.1-6.5 s not).
  if (l.bind == "core" || (l.bind == "auto" && over))
    a.insert(a.end(), {"--bind-to", over ? "core:overload-allowed" : "core"});
  else if (l.bind == "none")
    a.insert(a.end(), {"--bind-to", "none"});
  a.insert(a.end(), l.mpi_args.begin(), l.mpi_args.end());
  for (std::size_t i = 0; i < l.components.size(); ++i) {
    if (i) a.push_back(":");
    a.insert(a.end(), {"-np", std::to_string(l.ranks[i]), l.exes[i], config_path});
    if (!restart.empty()) a.insert(a.end(), {"--restart", restart});
  }
  return a;
}

// One field of an srun --multi-prog line: Slurm splits the line at
// whitespace, reads quotes and backslashes, and expands %t and %o; a
// backslash before any other character keeps it as it is.
std::string multi_prog_field(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (!std::isalnum(static_cast<unsigned char>(c)) &&
        std::string_view("_./=:,+@-").find(c) == std::string_view::npos)
      o += '\\';
    o += c;
  }
  return o;
}

// srun --multi-prog: one line per rank range, the program and its arguments.
std::string multi_prog(const Launch& l, const std::string& config_path, const std::string& restart) {
  std::string conf;
  int first = 0;
  for (std::size_t i = 0; i < l.components.size(); ++i) {
    conf += fmt::format("{}-{} {} {}{}\n", first, first + l.ranks[i] - 1, multi_prog_field(l.exes[i]),
                        multi_prog_field(config_path),
                        restart.empty() ? "" : " --restart " + multi_prog_field(restart));
    first += l.ranks[i];
  }
  return conf;
}

// The CPUs Slurm gives this step: the allocation's when inside
// one (SLURM_JOB_CPUS_PER_NODE summed over its nodes, e.g. "8" or "8(x2),4"),
// else this machine's.
int slurm_cpus() {
  if (const char* c = std::getenv("SLURM_JOB_CPUS_PER_NODE")) {
    // The whole allocation: "8(x2),4" is 8 on two nodes and 4 on a third.
    long total = 0;
    const char* p = c;
    while (true) {
      char* end = nullptr;
      const long n = std::strtol(p, &end, 10);
      if (end == p) break;
      long times = 1;
      if (std::strncmp(end, "(x", 2) == 0) {
        times = std::strtol(end + 2, &end, 10);
        if (*end == ')') ++end;
      }
      total += n * times;
      if (*end != ',') break;
      p = end + 1;
    }
    if (total > 0) return static_cast<int>(std::min(total, 1L << 30));
  }
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

// Debian's Open MPI runs under srun only through PMIx; --kill-on-bad-exit ends
// the step when any rank fails, so that a dead component never leaves the
// others waiting; --quit-on-interrupt ends it on one Ctrl-C (srun otherwise
// reports the tasks' state and waits for a second within a second);
// --overcommit where the ranks exceed the CPUs.
std::vector<std::string> srun_argv(const Launch& l, const std::string& conf_path) {
  std::vector<std::string> a{"srun", "--mpi=pmix",           "--kill-on-bad-exit=1", "--quit-on-interrupt",
                             "-n",   std::to_string(l.total)};
  if (l.total > slurm_cpus()) a.push_back("--overcommit");
  if (l.bind != "auto") a.push_back(l.bind == "core" ? "--cpu-bind=cores" : "--cpu-bind=none");
  a.insert(a.end(), l.mpi_args.begin(), l.mpi_args.end());
  a.insert(a.end(), {"--multi-prog", conf_path});
  return a;
}

// A path inside a double-quoted #SBATCH value: sbatch reads the quotes and
// backslashes, and --output's % as a pattern (a literal one is %%).
std::string sbatch_value(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\';
    o += c == '%' ? std::string("%%") : std::string(1, c);
  }
  return o;
}

// A Slurm batch script that runs this configuration with srun: the tasks of
// all components, a time limit from the pre-run report's estimate (x 1.5 +
// 10 min, at most a year; 1 h where no component estimates), the output beside the run's.
std::string sbatch_script(const Config& cfg, const Launch& l, const std::string& cfg_path,
                          const std::vector<std::string>& overrides, const std::string& restart, bool strict,
                          double estimate_s) {
  // In whole minutes, at most a year (an estimate of a run that long says
  // more about its end time than about Slurm's limit).
  const double minutes = std::min(std::ceil((1.5 * estimate_s + 600.0) / 60.0), 525600.0);
  const long limit = estimate_s > 0 ? static_cast<long>(minutes) * 60 : 3600;
  std::vector<std::string> cmd{self_dir() + "/coflow", "run", fs::absolute(cfg_path).string(), "--launcher", "srun"};
  for (const auto& o : overrides) cmd.insert(cmd.end(), {"--set", o});
  if (!restart.empty()) cmd.insert(cmd.end(), {"--restart", restart});
  for (std::size_t i = 0; i < l.components.size(); ++i)  // --exe: the executables not built beside the launcher
    if (l.own(i)) cmd.insert(cmd.end(), {"--exe", l.components[i] + "=" + l.exes[i]});
  if (strict) cmd.push_back("--strict");
  std::string ranks;
  for (std::size_t i = 0; i < l.components.size(); ++i)
    ranks += fmt::format("{}{} {}", i ? ", " : "", l.components[i], l.ranks[i]);
  return fmt::format(
      "#!/bin/bash\n"
      "# coflow run '{}': {} ({} tasks)\n"
      "#SBATCH --job-name={}\n"
      "#SBATCH --ntasks={}\n"
      "#SBATCH --time={:02d}:{:02d}:00   # {}\n"
      "#SBATCH --output=\"{}/slurm-%j.out\"\n"
      "set -euo pipefail\n"
      "cd {}\n"
      "exec {}\n",
      cfg.run.name, ranks, l.total, cfg.run.name, l.total, limit / 3600, (limit % 3600) / 60,
      estimate_s > 0 ? fmt::format("the pre-run report's estimate {} x 1.5 + 10 min",
                                   coflow::config::duration(estimate_s))
                     : std::string("no component estimates its wall time: 1 h"),
      sbatch_value(fs::absolute(cfg.output_dir()).string()), quoted(fs::current_path().string()),
      join_cmd(cmd));
}

// ------------------------------------------------------------- progress ---

class Progress {
 public:
  explicit Progress(bool tty) : tty_(tty) {}
  void update(double t, double end, long w, long windows, double wall) {
    const double frac = end > 0 ? std::clamp(t / end, 0.0, 1.0) : 1.0;
    const double rate = wall > 0 ? w / wall : 0.0;
    const double eta = rate > 0 ? (windows - w) / rate : 0.0;
    if (tty_) {
      const int width = 30, fill = static_cast<int>(frac * width);
      std::string bar(fill, '#');
      bar += std::string(width - fill, ' ');
      std::fprintf(stdout, "\r[%s] %5.1f%%  t = %.4g / %.4g s  %.1f windows/s  ETA %s   ", bar.c_str(),
                   100 * frac, t, end, rate, eta_text(eta).c_str());
      std::fflush(stdout);
      shown_ = true;
    } else if (frac >= next_ || w == windows) {
      std::fprintf(stdout, "progress: %3.0f%%  t = %.4g / %.4g s  %.1f windows/s  ETA %s\n", 100 * frac, t, end,
                   rate, eta_text(eta).c_str());
      std::fflush(stdout);
      next_ = std::floor(frac * 10 + 1e-9) / 10 + 0.1;
    }
  }
  void clear() {
    if (tty_ && shown_) {
      std::fprintf(stdout, "\r%*s\r", 110, "");
      std::fflush(stdout);
      shown_ = false;
    }
  }
  void done() {
    if (tty_ && shown_) std::fprintf(stdout, "\n");
    shown_ = false;
  }

 private:
  static std::string eta_text(double s) {
    if (s < 60) return fmt::format("{:.0f} s", s);
    if (s < 3600) return fmt::format("{:.0f} min {:02.0f} s", std::floor(s / 60), std::fmod(s, 60));
    return fmt::format("{:.1f} h", s / 3600);
  }
  bool tty_;
  bool shown_ = false;
  double next_ = 0.0;
};

struct Failure {
  std::string component;
  std::string rank;
  std::string reason;
};

// The launcher's own report of a process that died: Open MPI's "process rank
// N ... exited on signal / non-zero status", srun's "task N: Exited with exit
// code / Killed / Terminated". The world rank N names the component.
Failure dead_process(const std::string& s, const Launch& launch) {
  long r = -1;
  if (const auto at = s.find("process rank "); at != std::string::npos &&
      (s.find("exited on signal") != std::string::npos || s.find("non-zero status") != std::string::npos))
    r = std::atol(s.c_str() + at + 13);
  if (const auto at = s.find(": task "); s.rfind("srun: error:", 0) == 0 && at != std::string::npos &&
      (s.find("Exited with exit code") != std::string::npos || s.find("Killed") != std::string::npos ||
       s.find("Terminated") != std::string::npos || s.find("Segmentation") != std::string::npos))
    r = std::atol(s.c_str() + at + 7);
  long first = 0;
  for (std::size_t i = 0; r >= 0 && i < launch.components.size(); ++i) {
    if (r < first + launch.ranks[i]) return {launch.components[i], std::to_string(r - first), s};
    first += launch.ranks[i];
  }
  return {};
}

// What the launcher reads from the components' combined output.
struct Watch {
  const Launch& launch;
  Progress& progress;
  Failure& failure;
  std::set<std::string> started;  // components whose rank 0 logged "coflow-<component> started"
};

// One line of the components' output: progress and failure tags are taken,
// everything else is shown. A tag is found anywhere in its line: mpi_args
// such as mpirun --tag-output or --timestamp-output and srun --label put a
// prefix before it.
void take_line(const std::string& s, Watch& w) {
  const std::string ptag = coflow::coupler::kProgressTag, ftag = coflow::coupler::kFailedTag;
  if (const auto at = s.find(ptag); at != std::string::npos) {
    double t = 0, end = 0, wall = 0;
    long win = 0, n = 0;
    if (std::sscanf(s.c_str() + at + ptag.size(), "%lf %lf %ld %ld %lf", &t, &end, &win, &n, &wall) == 5)
      w.progress.update(t, end, win, n, wall);
    return;
  }
  if (const auto at = s.find(ftag); at != std::string::npos) {
    std::istringstream is(s.substr(at + ftag.size()));
    Failure f;
    is >> f.component >> f.rank;
    std::getline(is, f.reason);
    if (!f.reason.empty() && f.reason[0] == ' ') f.reason.erase(0, 1);
    if (w.failure.component.empty()) w.failure = f;
    return;
  }
  for (const auto& c : w.launch.components)
    if (s.find("coflow-" + c + " started:") != std::string::npos) w.started.insert(c);
  if (w.failure.component.empty()) w.failure = dead_process(s, w.launch);
  w.progress.clear();
  std::fprintf(stderr, "%s\n", s.c_str());
  std::fflush(stderr);
}

// The components that have not started after `limit` seconds (an executable
// that exits or hangs before joining holds the others in MPI start-up, where
// no timeout of theirs runs): the launch is stopped and they are named.
bool start_overdue(Watch& w, double since, double limit, pid_t pid) {
  if (w.started.size() == w.launch.components.size() || coflow::coupler::now() - since < limit) return false;
  std::string missing, own;
  for (std::size_t i = 0; i < w.launch.components.size(); ++i) {
    const std::string& c = w.launch.components[i];
    if (!w.started.count(c)) missing += (missing.empty() ? "" : ", ") + c;
    if (w.launch.own(i)) own += fmt::format(" {}={}", c, w.launch.exes[i]);
  }
  // One executable that never starts MPI holds every other in MPI start-up.
  const std::string suspect = own.empty() ? std::string() : fmt::format("; your own executables:{}", own);
  if (w.failure.component.empty())  // a component's own reason, when it gave one, stays the reason
    w.failure = {
        missing, "",
        fmt::format("{} did not start within {:.0f} s (run.launch.start_timeout): an executable exited or "
                    "hangs before joining the run, which holds the others in MPI start-up{}",
                    missing, limit, suspect)};
  kill(pid, SIGTERM);
  return true;
}

// Reads the launch's output until it ends (every process that holds the
// pipe is gone). The start watchdog's SIGTERM is escalated: a launcher (mpirun
// or srun) still there run.launch.stop_grace s after it is killed (SIGKILL;
// the ranks, which Open MPI starts in process groups of their own, lose their
// server), and stop_grace s after that the pipe is abandoned, whatever still
// holds it, so that nothing keeps the launcher waiting. Returns whether the
// watchdog stopped the launch.
bool read_child_output(int fd, Watch& w, std::string& buf, double since,
                       const coflow::config::LaunchParams& limits, pid_t pid) {
  const double grace = limits.stop_grace;
  double stopped_at = -1, killed_at = -1;
  char chunk[4096];
  for (;;) {
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, 1000) > 0) {
      const ssize_t n = read(fd, chunk, sizeof chunk);
      if (n < 0 && errno == EINTR) continue;  // a signal (forwarded to the child) is no end of its output
      if (n <= 0) break;
      buf.append(chunk, static_cast<std::size_t>(n));
      for (std::size_t nl; (nl = buf.find('\n')) != std::string::npos; buf.erase(0, nl + 1))
        take_line(buf.substr(0, nl), w);
    }
    const double t = coflow::coupler::now();
    if (stopped_at < 0) {
      if (start_overdue(w, since, limits.start_timeout, pid)) stopped_at = t;
    } else if (killed_at < 0 && t - stopped_at > grace) {
      std::fprintf(stderr,
                   "coflow: the launch did not end %g s after SIGTERM (run.launch.stop_grace): killing it\n",
                   grace);
      kill(pid, SIGKILL);
      killed_at = t;
    } else if (killed_at >= 0 && t - killed_at > grace) {
      break;  // a process that outlived the launcher still holds the pipe
    }
  }
  return stopped_at >= 0;
}

// Runs argv with stdout+stderr piped to us; returns the exit status.
int run_child(const std::vector<std::string>& argv, const Launch& launch, Progress& progress,
              Failure& failure, const coflow::config::LaunchParams& limits) {
  int fds[2];
  if (pipe(fds) != 0) throw std::runtime_error("pipe failed");
  std::vector<char*> cargv;
  for (const auto& a : argv) cargv.push_back(const_cast<char*>(a.c_str()));
  cargv.push_back(nullptr);
  // The handlers come first, with SIGINT, SIGTERM and SIGHUP blocked over the
  // fork and g_child's assignment: one sent meanwhile waits and is then
  // forwarded (it would otherwise end the launcher and leave the child
  // running). The child takes the default actions back, unblocked, before its
  // exec. A hangup ignored already (nohup coflow run ...) stays ignored, in the
  // launcher and in its child.
  struct sigaction hangup {};
  sigaction(SIGHUP, nullptr, &hangup);
  const bool nohup = hangup.sa_handler == SIG_IGN;
  std::vector<int> forwarded{SIGINT, SIGTERM};
  if (!nohup) forwarded.push_back(SIGHUP);
  sigset_t stop, old;
  sigemptyset(&stop);
  for (const int sig : forwarded) sigaddset(&stop, sig);
  sigprocmask(SIG_BLOCK, &stop, &old);
  for (const int sig : forwarded) signal(sig, forward_signal);
  const pid_t pid = fork();
  if (pid < 0) {
    for (const int sig : forwarded) signal(sig, SIG_DFL);  // no child: Ctrl-C ends the launcher
    sigprocmask(SIG_SETMASK, &old, nullptr);
    close(fds[0]);
    close(fds[1]);
    throw std::runtime_error("fork failed");
  }
  if (pid == 0) {
    for (const int sig : forwarded) signal(sig, SIG_DFL);
    signal(SIGPIPE, SIG_DFL);  // ignored in the launcher; an ignored signal stays so over exec
    sigprocmask(SIG_SETMASK, &old, nullptr);
    // Components read no input: mpirun would otherwise forward the terminal
    // to rank 0.
    if (const int null = open("/dev/null", O_RDONLY); null >= 0) {
      dup2(null, STDIN_FILENO);
      if (null != STDIN_FILENO) close(null);
    }
    dup2(fds[1], STDOUT_FILENO);
    dup2(fds[1], STDERR_FILENO);
    close(fds[0]);
    close(fds[1]);
    execvp(cargv[0], cargv.data());
    std::fprintf(stderr, "coflow: cannot start %s: %s\n", cargv[0], std::strerror(errno));
    _exit(127);
  }
  g_child = pid;
  sigprocmask(SIG_SETMASK, &old, nullptr);  // a signal that waited is forwarded now
  close(fds[1]);
  Watch w{launch, progress, failure, {}};
  const double since = coflow::coupler::now();
  std::string buf;
  const bool stopped = read_child_output(fds[0], w, buf, since, limits, pid);
  if (!buf.empty()) take_line(buf, w);
  close(fds[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  g_child = 0;
  progress.done();
  if (WIFEXITED(status)) return WEXITSTATUS(status) == 0 && stopped ? 1 : WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return 1;
}

// The rank split that would balance the run of this summary, or "".
std::string split_advice(const YAML::Node& s) {
  std::vector<coflow::coupler::ComponentLoad> loads;
  for (const auto& c : coflow::config::component_order()) {
    const YAML::Node n = s["components"][c];
    if (n) loads.push_back({c, n["ranks"].as<int>(), n["compute_s"].as<double>()});
  }
  return coflow::coupler::rank_advice(loads, s["scheme"].as<std::string>() == "parallel-explicit");
}

// Whether dir holds the summary of a finished run ("status": "ok"). Looked
// for again for up to 2 s: under srun, world rank 0 may write it on another
// node, whose file may reach this node's view of a shared directory late.
bool finished_summary(const std::string& dir) {
  for (int attempt = 0; attempt < 20; ++attempt) {
    try {
      if (YAML::LoadFile(dir + "/summary.json")["status"].as<std::string>() == "ok") return true;
    } catch (const std::exception&) {
    }
    usleep(100000);
  }
  return false;
}

// A finished run's table (finished_summary has found it).
void print_summary(const std::string& dir) {
  YAML::Node s;
  try {
    s = YAML::LoadFile(dir + "/summary.json");
  } catch (const std::exception&) {
    return;
  }
  std::printf("\ncoflow: run '%s' finished in %.2f s wall (%ld windows of %.4g s, %s)\n",
              s["name"].as<std::string>().c_str(), s["wall_s"].as<double>(), s["windows"].as<long>(),
              s["window"].as<double>(), s["scheme"].as<std::string>().c_str());
  std::printf("  %-10s %-16s %5s %9s %10s %10s %10s %10s %12s\n", "component", "variant", "ranks", "steps",
              "wall s", "compute s", "exchange s", "wait s", "MB moved");
  for (const auto& c : coflow::config::component_order()) {
    const YAML::Node n = s["components"][c];
    if (!n) continue;
    std::printf("  %-10s %-16s %5d %9ld %10.3f %10.3f %10.3f %10.3f %12.2f\n", c.c_str(),
                n["variant"].as<std::string>().c_str(), n["ranks"].as<int>(), n["steps"].as<long>(),
                n["wall_s"].as<double>(), n["compute_s"].as<double>(), n["exchange_s"].as<double>(),
                n["wait_s"].as<double>(),
                (n["bytes_sent"].as<double>() + n["bytes_received"].as<double>()) / 1e6);
  }
  std::printf("  output: %s  (open %s/run.xdmf in ParaView)\n", dir.c_str(), dir.c_str());
  if (const std::string advice = split_advice(s); !advice.empty())
    std::printf("  ranks: %s\n", advice.c_str());
}

// `coflow validate`: the split the last run of this configuration suggests.
void print_last_run_advice(const Config& cfg) {
  try {
    const YAML::Node s = YAML::LoadFile(cfg.output_dir() + "/summary.json");
    if (s["status"].as<std::string>() != "ok") return;
    if (const std::string advice = split_advice(s); !advice.empty())
      std::printf("# ranks (the last run in %s): %s\n", cfg.output_dir().c_str(), advice.c_str());
  } catch (const std::exception&) {  // no last run, or not a complete one: nothing to say
  }
}

// The failed rank as a JSON number, or null where no rank is known (an
// interrupted run, a start that never came).
std::string json_rank(const std::string& rank) {
  const bool number =
      !rank.empty() && rank.size() < 10 && rank.find_first_not_of("0123456789") == std::string::npos;
  return number ? std::to_string(std::stol(rank)) : "null";
}

void write_failed_summary(const Config& cfg, const Failure& f, int code, double wall) {
  const std::string dir = cfg.output_dir();
  std::error_code ec;
  fs::create_directories(dir, ec);
  const std::string json = fmt::format(
      "{{\n  \"name\": {},\n  \"status\": \"failed\",\n  \"failed_component\": {},\n  \"failed_rank\": {},\n"
      "  \"reason\": {},\n  \"exit_code\": {},\n  \"wall_s\": {:.6f}\n}}\n",
      coflow::output::json_quote(cfg.run.name),
      f.component.empty() ? "null" : coflow::output::json_quote(f.component), json_rank(f.rank),
      coflow::output::json_quote(f.reason), code, wall);
  try {
    coflow::output::atomic_write(dir + "/summary.json", json);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "coflow: the failed run's summary could not be written: %s%s\n", e.what(),
                 coflow::output::low_space_note(dir).c_str());
  }
}

// The launcher (mpirun or srun) and every component executable must be there.
int check_executables(const std::string& launcher, const Launch& launch) {
  if (find_in_path(launcher).empty()) {
    std::cerr << "coflow: '" << launcher << "' not found; "
              << (launcher == "srun" ? "run where Slurm is installed, or use --launcher mpirun"
                                     : "install Open MPI (scripts/setup does)")
              << "\n";
    return 1;
  }
  for (const auto& exe : launch.exes)
    if (access(exe.c_str(), X_OK) != 0) {
      std::cerr << "coflow: component executable " << exe << " is missing; build it (scripts/setup)\n";
      return 1;
    }
  if (geteuid() == 0) {
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  }
  // More ranks than cores: ranks waiting in MPI give their core away instead of
  // spinning (srun does not tell Open MPI that the node is oversubscribed).
  if (launch.total > physical_cores()) setenv("OMPI_MCA_mpi_yield_when_idle", "1", 0);
  // A failing component calls MPI_Abort after it has written its reason;
  // Open MPI then sends SIGTERM to every rank and waits this many seconds
  // (default 1) before SIGKILL, even when all are gone: a failed run ended
  // 1.0 s later than it had to (fv_ke_decay from a damaged checkpoint, 1.51 s
  // against 0.52 s). No coflow component handles SIGTERM, so nothing is lost;
  // a user's own executable (--exe) may, and keeps Open MPI's grace.
  bool own = false;
  for (std::size_t i = 0; i < launch.exes.size(); ++i) own = own || launch.own(i);
  if (!own) setenv("OMPI_MCA_odls_base_sigkill_timeout", "0", 0);
  return 0;
}

// A fresh run directory (stale snapshots or a stale summary would mislead),
// and the resolved configuration the components read.
void prepare_run_directory(const Config& cfg, const std::string& dir, const std::string& restart) {
  if (restart.empty()) {
    std::error_code ec;
    for (const char* sub : {"fluid", "particles", "immersed", "series", "events", "logs"}) fs::remove_all(dir + "/" + sub, ec);
    // An earlier run's checkpoints would be counted with this run's (and
    // pruned in their place), and --restart latest would take them.
    if (const auto old = coflow::coupler::complete_checkpoints(dir); !old.empty())
      std::printf(
          "coflow: a fresh run: the %zu checkpoint(s) of the run before it in %s/checkpoints are removed "
          "(use --restart to go on from one)\n",
          old.size(), dir.c_str());
    fs::remove_all(dir + "/checkpoints", ec);
    fs::remove(dir + "/summary.json", ec);
    fs::remove(dir + "/run.xdmf", ec);
  } else {  // said at every restart, whether or not the rewind had anything to remove
    const std::string said = coflow::launcher::rewind_run_directory(cfg, dir, restart);
    std::printf("coflow: restarting from %s%s\n%s", restart.c_str(),
                said.empty() ? "" : ": the run directory goes back to that time", said.c_str());
  }
  fs::create_directories(dir);
  coflow::output::atomic_write(dir + "/config.yaml", YAML::Dump(cfg.resolved) + "\n");
}

// After Ctrl-C (or SIGTERM, or a hangup): what was written, and how to go on from it.
int report_interrupted(const std::string& cfg_path, const std::vector<std::string>& overrides,
                       const std::string& extra, const std::string& dir, int rc, double wall,
                       const Config& cfg) {
  const std::vector<std::string> checkpoints = coflow::coupler::complete_checkpoints(dir);
  write_failed_summary(cfg, {"", "", fmt::format("interrupted by signal {} after {:.1f} s", int(g_interrupted), wall)},
                       rc, wall);
  std::fprintf(stderr, "\ncoflow: interrupted after %.1f s; snapshots and series written so far are in %s/\n", wall,
               dir.c_str());
  if (checkpoints.empty())
    std::fprintf(stderr, "  no checkpoint was written (set run.checkpoint.every to be able to restart)\n");
  else
  {
    std::string sets;
    for (const auto& o : overrides) sets += " --set " + ::quoted(o);
    std::fprintf(stderr, "  restart from the last checkpoint with:\n    coflow run %s%s%s --restart %s\n",
                 ::quoted(fs::absolute(cfg_path).string()).c_str(), sets.c_str(), extra.c_str(),
                 ::quoted(checkpoints.back()).c_str());
  }
  return 128 + int(g_interrupted);
}

// --------------------------------------------------------------- docs -----

// The coupling contracts (coflow/contract.hpp) as a table: what `coflow
// validate` matches. Needs that depend on a variant's keys are noted below it.
void print_contracts() {
  using namespace coflow::config;
  std::printf("\n## Coupling contracts\n\n"
              "What each variant provides to the other components, what it needs from them (a need\n"
              "marked *with X* holds only when component X is in the run) and which coupling schemes\n"
              "it runs. `coflow validate` rejects a run whose needs no other component meets, or\n"
              "whose scheme a variant does not run. An `external` variant's contract is open.\n\n"
              "| variant | provides | needs | schemes |\n|---|---|---|---|\n");
  const Config none;
  auto join_fields = [](const std::vector<Field>& f) {
    std::string out;
    for (const auto& x : f) out += (out.empty() ? "" : ", ") + x.name;
    return out.empty() ? std::string("–") : out;
  };
  for (const auto& schema : coflow::catalog()) {
    if (!schema.contract) continue;
    for (const auto& v : schema.variants) {
      if (v == "external") continue;
      const Contract c = schema.contract(none, v);
      std::string needs, schemes;
      for (const auto& n : c.needs)
        needs += (needs.empty() ? "" : ", ") + n.field.name + (n.only_with.empty() ? "" : " *with " + n.only_with + "*");
      for (Scheme sc : c.schemes) schemes += (schemes.empty() ? "" : ", ") + std::string(scheme_name(sc));
      std::printf("| `%s.%s: %s` | %s | %s | %s |\n", schema.section.c_str(), schema.selector.c_str(), v.c_str(),
                  join_fields(c.provides).c_str(), needs.empty() ? "–" : needs.c_str(), schemes.c_str());
    }
  }
  std::printf(
      "\nThe table is each variant's contract without keys. Some keys add to it:\n"
      "- `fv` and `fv-reference` with `fluid.turbulence` also provide `k` and `epsilon`;\n"
      "- `psm` with a two-fluid `lbm` or `lbm-reference` (`fluid.two_phase`) also provides\n"
      "  `grain_wetting` (each species' contact angle);\n"
      "- `ibm` with `immersed.ibm.particles: point` also takes `point`'s part: provides\n"
      "  fluid_at_particle and momentum_source, needs velocity, particle_state and impulse, and\n"
      "  runs serial-explicit only;\n"
      "- `particles.dispersion.model: langevin` (dpm) also needs `k` and `epsilon` from the fluid\n"
      "  (`analytic`, or `fv` with `fluid.turbulence`).\n\n"
      "Fields: velocity, pressure, k, epsilon, solid_fraction, solid_force and momentum_source live\n"
      "on fluid cells; particle_state, hydrodynamic_load, fluid_at_particle and impulse at the\n"
      "particles (docs/protocol.md).\n");
}

void print_variants(bool markdown) {
  using coflow::config::Describer;
  if (markdown) {
    std::printf("# coflow configuration reference\n\n");
    std::printf("Generated by `coflow variants --markdown` from the same declarations the parser\n"
                "uses; `tests` check that this file is up to date. All quantities are SI.\n\n");
    std::printf("| key | type | default | rule | meaning |\n|---|---|---|---|---|\n");
    Describer d;
    coflow::config::describe_config(d, coflow::catalog());
    auto cell = [](std::string s) {  // a '|' would end the table cell
      for (std::size_t at = 0; (at = s.find('|', at)) != std::string::npos; at += 2) s.replace(at, 1, "\\|");
      return s;
    };
    for (const auto& r : d.rows())
      std::printf("| `%s` | %s | %s | %s | %s |\n", r.path.c_str(), cell(r.type).c_str(),
                  r.default_value.empty() ? "" : ("`" + cell(r.default_value) + "`").c_str(), cell(r.rule).c_str(),
                  cell(r.doc).c_str());
    std::printf("\n## Variants\n\n");
    for (const auto& v : coflow::variant_infos())
      std::printf("- `%s.%s = %s`: %s\n", v.component.c_str(), v.component == "immersed" ? "method" : "solver",
                  v.name.c_str(), v.summary.c_str());
    std::printf("- `<component>.solver|method = external`: your own executable, run with "
                "`coflow run --exe <component>=PATH` (see docs/protocol.md).\n");
    print_contracts();
    return;
  }
  for (const auto& comp : coflow::config::component_order()) {
    std::printf("%s:\n", comp.c_str());
    for (const auto& v : coflow::variant_infos()) {
      if (v.component != comp) continue;
      std::printf("  %-16s %s\n", v.name.c_str(), v.summary.c_str());
      if (v.params_section.empty()) continue;
      Describer d(comp + "." + v.params_section);
      v.describe(d);
      for (const auto& r : d.rows())
        std::printf("      %-34s %-16s default %-10s %s%s%s\n", r.path.c_str(), r.type.c_str(),
                    r.default_value.c_str(), r.doc.c_str(), r.rule.empty() ? "" : "; ", r.rule.c_str());
    }
    std::printf("  %-16s your own executable: coflow run --exe %s=PATH (docs/protocol.md)\n", "external", comp.c_str());
  }
}

// The options of `coflow run`.
struct RunOptions {
  std::string cfg_path, launcher = "mpirun", restart;
  std::vector<std::string> overrides, exes;
  bool dry = false;
  bool strict = false;
};

// The pre-run report (coflow/report.hpp), with `prefix` on each line. With
// --strict a warning fails the command (exit status 2).
int print_report(const Config& cfg, const RunOptions& o, const std::string& prefix, std::FILE* out) {
  const coflow::config::Report r = coflow::config::pre_run_report(cfg, coflow::catalog());
  std::fprintf(out, "%s", r.text(prefix).c_str());
  std::fflush(out);
  if (o.strict && !r.warnings.empty()) {
    std::fprintf(stderr, "%s: %zu warning(s) and --strict: not running; fix them or leave out --strict\n",
                 o.cfg_path.c_str(), r.warnings.size());
    return 2;
  }
  return 0;
}

// --exe COMPONENT=PATH: the executables that replace the built-in ones.
// Returns exit status 2, with a message, on a bad one.
int read_exe_overrides(const Config& cfg, const std::vector<std::string>& exes,
                       std::map<std::string, std::string>& out) {
  for (const auto& e : exes) {
    const auto eq = e.find('=');
    const std::string comp = e.substr(0, eq == std::string::npos ? 0 : eq);
    const auto& order = coflow::config::component_order();
    if (eq == std::string::npos || std::find(order.begin(), order.end(), comp) == order.end()) {
      std::cerr << "--exe " << e << ": expected COMPONENT=PATH with COMPONENT one of fluid, immersed, particles\n";
      return 2;
    }
    if (!cfg.has(comp)) {
      std::cerr << "--exe " << e << ": " << cfg.file << " has no " << comp
                << " section, so nothing would run it: add one (" << comp
                << ": {solver: external, ...}) or leave out this --exe\n";
      return 2;
    }
    const std::string path = e.substr(eq + 1);
    if (!fs::exists(path)) {
      std::cerr << "--exe " << e << ": no such file\n";
      return 2;
    }
    if (!fs::is_regular_file(path) || access(path.c_str(), X_OK) != 0) {
      std::cerr << "--exe " << e << ": not an executable file (chmod +x it, or give the built program)\n";
      return 2;
    }
    out[comp] = e.substr(eq + 1);
  }
  return 0;
}

// Each rank that fails leaves logs/FAILED.<component>.<rank>; the run's
// logs/FAILED lists them, the earliest first, and replaces them.
void gather_failures(const std::string& dir) {
  std::error_code ec;
  std::vector<std::pair<fs::file_time_type, fs::path>> pieces;
  for (const auto& e : fs::directory_iterator(dir + "/logs", ec))
    if (const std::string name = e.path().filename().string(); name.rfind("FAILED.", 0) != 0)
      continue;
    else if (name.find(".tmp.") != std::string::npos)
      fs::remove(e.path(), ec);  // a rank killed while it wrote its piece
    else
      pieces.emplace_back(e.last_write_time(ec), e.path());
  if (pieces.empty()) return;
  std::sort(pieces.begin(), pieces.end());
  std::string all;
  for (const auto& [when, path] : pieces) {
    std::ifstream in(path);
    all += std::string(std::istreambuf_iterator<char>(in), {});
  }
  std::ofstream out(dir + "/logs/FAILED", std::ios::app);
  out << all;
  out.close();
  if (!out) return;  // not written (a full disk): the pieces stay in logs/ for the user to read
  for (const auto& [when, path] : pieces) fs::remove(path, ec);
}

// A failed run: name the component and its reason (from its own report, or
// from logs/FAILED), write the summary, and return the launcher's exit status.
int report_failure(const Config& cfg, const std::string& dir, Failure failure, int rc, double wall) {
  gather_failures(dir);
  if (failure.component.empty()) {
    std::ifstream f(dir + "/logs/FAILED");
    std::string first;
    if (std::getline(f, first)) {
      std::istringstream is(first);  // "<component> rank <N>: <reason>"
      std::string word, rank;
      is >> failure.component >> word >> rank;
      if (word == "rank" && !rank.empty() && rank.back() == ':')
        failure.rank = rank.substr(0, rank.size() - 1);
      failure.reason = first;
    }
  }
  if (failure.reason.empty())
    failure.reason = fmt::format("the launch ended with exit status {} and no component reported why", rc);
  write_failed_summary(cfg, failure, rc, wall);
  if (failure.component.empty() && rc == 0)
    std::fprintf(stderr, "\ncoflow: run failed: %s\n", failure.reason.c_str());
  else if (failure.component.empty() && fs::exists(dir + "/logs"))
    // A restart keeps the earlier run's logs: mpirun's own output comes first.
    std::fprintf(stderr,
                 "\ncoflow: run failed (exit status %d) and no component said why: see the MPI launcher's "
                 "output above, then %s/logs/\n",
                 rc, dir.c_str());
  else if (failure.component.empty())
    std::fprintf(stderr,
                 "\ncoflow: run failed (exit status %d) before any component started (no logs were "
                 "written): the MPI launcher or an executable stopped at start; see the output above (an "
                 "entry of run.launch.mpi_args, too few slots, or an --exe that is not a coflow "
                 "component)\n",
                 rc);
  else
    std::fprintf(stderr, "\ncoflow: run failed in component '%s'%s: %s\n%s\n", failure.component.c_str(),
                 failure.rank.empty() ? "" : fmt::format(" (rank {})", failure.rank).c_str(), failure.reason.c_str(),
                 fs::exists(dir + "/logs") ? fmt::format("  logs: {}/logs/", dir).c_str() : "  (no logs were written)");
  return rc == 2 ? 2 : 1;
}

// One run at a time in a run directory: the launcher holds an exclusive lock
// on <dir>/.coflow.lock until it exits (flock: released also when it dies). A
// second run into the directory would empty it under the first.
int lock_run_directory(const std::string& dir) {
  fs::create_directories(dir);
  const std::string path = dir + "/.coflow.lock";
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) {
    std::fprintf(stderr, "coflow: cannot open %s: %s\n", path.c_str(), std::strerror(errno));
    return 2;
  }
  if (::flock(fd, LOCK_EX | LOCK_NB) == 0)
    return 0;  // the descriptor stays open, and the lock held, until exit
  if (errno != EWOULDBLOCK) {
    // A file system without locks (Lustre noflock, NFS nolock): say so, go on.
    std::fprintf(stderr, "coflow: warning: cannot lock %s (%s): a second run into %s would not be stopped\n",
                 path.c_str(), std::strerror(errno), dir.c_str());
    return 0;
  }
  std::fprintf(
      stderr,
      "coflow: %s is in use by another coflow run (it holds %s): wait for that run to end, or choose "
      "another directory with --set run.output.dir=...\n",
      dir.c_str(), path.c_str());
  ::close(fd);
  return 2;
}

// A component whose variant is `external` runs the user's executable, which
// only --exe names: without it, exit 2 before any rank starts (the built-in
// executable would start and refuse the variant).
// The problem's place: the file's item, when it says `value` (a --set may have
// replaced it, and a --set value has no place in the file).
template <class Find>
void place_in_file(coflow::config::Problem& p, const std::string& cfg_path, Find find,
                   const std::string& value) {
  try {
    const YAML::Node n = find(YAML::LoadFile(cfg_path));
    if (n && n.IsScalar() && n.Scalar() == value && n.Mark().line >= 0)
      p.line = n.Mark().line + 1, p.column = n.Mark().column + 1;
  } catch (const std::exception&) {
  }
}

int check_external(const Config& cfg, const std::string& cfg_path,
                   const std::map<std::string, std::string>& exes) {
  for (const auto& schema : coflow::catalog()) {
    if (!cfg.has(schema.section) || cfg.component(schema.section).variant != "external" ||
        exes.count(schema.section))
      continue;
    coflow::config::Problem p{cfg_path, 0, 0, schema.section + "." + schema.selector,
                              fmt::format("'external' runs your own executable: give it with --exe {}=PATH "
                                          "(docs/protocol.md)",
                                          schema.section)};
    place_in_file(
        p, cfg_path, [&](const YAML::Node& f) { return f[schema.section][schema.selector]; }, "external");
    std::fprintf(stderr, "%s\n", p.format().c_str());
    return 2;
  }
  return 0;
}

// srun's -o/--output and -e/--error (also attached, -ofile, or abbreviated,
// --out=file) send the tasks' output to files, where the launcher sees
// neither their start, their progress nor their failure: its start watchdog
// would stop a healthy run after run.launch.start_timeout. Under srun and sbatch such
// mpi_args exit 2 before any rank starts (mpirun's --output-filename still
// copies to the terminal; Open MPI 5's --output tag only marks lines).
// A bundle of srun's short options that reaches -o or -e: the options before
// it take no argument (-l, -v, -Q, -u, ... as in -lo file); any other letter
// takes the rest of the word as its argument (-poutput is a partition), or,
// ending the word, the next word (`takes_next`: -J -lo names the job -lo).
bool srun_short_output(const std::string& a, bool& takes_next) {
  takes_next = false;
  if (a.size() < 2 || a[0] != '-' || a[1] == '-') return false;
  const std::string no_argument = "EHOQXZhlsuvV", optional = "IkK";
  for (std::size_t k = 1; k < a.size(); ++k) {
    if (a[k] == 'o' || a[k] == 'e') return true;
    if (no_argument.find(a[k]) == std::string::npos) {
      takes_next = k + 1 == a.size() && optional.find(a[k]) == std::string::npos;
      return false;
    }
  }
  return false;
}

int check_srun_output(const Config& cfg, const std::string& cfg_path, const std::string& launcher) {
  if (launcher == "mpirun") return 0;
  const auto& args = cfg.run.launch.mpi_args;
  bool argument = false;  // this word is the previous short option's argument
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (std::exchange(argument, false)) continue;
    const std::string name = a.rfind("--", 0) == 0 ? a.substr(2, a.find('=') - 2) : "";
    // srun takes any unambiguous prefix of a long option: --ou and --er are
    // the shortest for --output and --error.
    const bool long_form = name.size() >= 2 && (std::string("output").rfind(name, 0) == 0 ||
                                                std::string("error").rfind(name, 0) == 0);
    if (!long_form && !srun_short_output(a, argument)) continue;
    coflow::config::Problem p{
        cfg_path, 0, 0, "run.launch.mpi_args",
        fmt::format("'{}' sends the components' output to files under srun, where the "
                    "launcher cannot read their start, progress and failures: remove it "
                    "(each component's output is in <run.output.dir>/logs/)",
                    a)};
    place_in_file(
        p, cfg_path, [&](const YAML::Node& f) { return f["run"]["launch"]["mpi_args"][i]; }, a);
    std::fprintf(stderr, "%s\n", p.format().c_str());
    return 2;
  }
  return 0;
}

// --launcher sbatch: the batch script (printed with --dry-run, else written
// into the run directory and handed to sbatch, which prints the job id).
int submit_batch(const Config& cfg, const Launch& launch, const RunOptions& o) {
  const coflow::config::Report r = coflow::config::pre_run_report(cfg, coflow::catalog());
  const std::string script = sbatch_script(cfg, launch, o.cfg_path, o.overrides, o.restart, o.strict, r.wall_seconds);
  if (o.dry) {
    std::printf("%s", script.c_str());
    return 0;
  }
  std::map<std::string, std::string> exes;
  if (const int rc = read_exe_overrides(cfg, o.exes, exes); rc != 0) return rc;
  if (const int rc = check_external(cfg, o.cfg_path, exes); rc != 0) return rc;
  if (const int rc = print_report(cfg, o, "", stdout); rc != 0) return rc;
  if (find_in_path("sbatch").empty()) {
    std::fprintf(stderr, "coflow: sbatch not found: run on a Slurm login node, or use --launcher srun or mpirun\n");
    return 2;
  }
  fs::create_directories(cfg.output_dir());
  const std::string path = cfg.output_dir() + "/job.sbatch";
  coflow::output::atomic_write(path, script);
  std::fflush(stdout);
  const int rc = std::system(("sbatch " + quoted(path)).c_str());
  return rc == 0 ? 0 : 1;
}

// `coflow run` on a valid configuration: plan, launch, follow, report.
int run(const Config& cfg, RunOptions o) {
  std::map<std::string, std::string> exe_override;
  if (const int rc = read_exe_overrides(cfg, o.exes, exe_override); rc != 0) return rc;
  if (const int rc = coflow::launcher::resolve_restart(cfg, o.restart); rc != 0) return rc;

  if (const int rc = check_srun_output(cfg, o.cfg_path, o.launcher); rc != 0) return rc;
  const Launch launch = plan(cfg, exe_override);
  const std::string dir = cfg.output_dir();
  const std::string resolved = dir + "/config.yaml";
  const std::string conf_path = dir + "/multi-prog.conf";
  if (o.launcher == "sbatch") return submit_batch(cfg, launch, o);
  const bool srun = o.launcher == "srun";
  const auto argv_launch = srun ? srun_argv(launch, conf_path) : mpirun_argv(launch, resolved, o.restart);
  if (o.dry) {
    std::printf("%s\n", join_cmd(argv_launch).c_str());
    if (srun) std::printf("%s", multi_prog(launch, resolved, o.restart).c_str());
    return 0;
  }
  if (const int rc = check_external(cfg, o.cfg_path, exe_override); rc != 0) return rc;
  if (const int rc = check_executables(argv_launch[0], launch); rc != 0) return rc;
  if (const int rc = print_report(cfg, o, "", stdout); rc != 0) return rc;
  std::error_code same_ec;
  if (fs::equivalent(o.cfg_path, resolved, same_ec)) {
    std::fprintf(
        stderr,
        "%s: the configuration is the run directory's config.yaml, which a run rewrites with the resolved "
        "configuration: copy it elsewhere and run that, or choose another run.output.dir\n",
        o.cfg_path.c_str());
    return 2;
  }
  if (const int rc = lock_run_directory(dir); rc != 0) return rc;
  prepare_run_directory(cfg, dir, o.restart);
  if (srun) coflow::output::atomic_write(conf_path, multi_prog(launch, resolved, o.restart));

  std::printf("coflow: running '%s' with %s\n", cfg.run.name.c_str(),
              fmt::format("{}", fmt::join(launch.components, " + ")).c_str());
  std::fflush(stdout);
  Progress progress(isatty(STDOUT_FILENO));
  Failure failure;
  const double t0 = coflow::coupler::now();
  const int rc = run_child(argv_launch, launch, progress, failure, cfg.run.launch);
  const double wall = coflow::coupler::now() - t0;
  if (rc == 0 && finished_summary(dir)) {
    print_summary(dir);
    return 0;
  }
  if (rc == 0 && failure.reason.empty())  // every process exited 0, but none finished the run
    failure.reason = fmt::format(
        "the launch ended with exit status 0, but {}/summary.json does not hold a finished run: a component "
        "exited without finishing it (an --exe program that does not run coflow's session?)",
        dir);
  if (g_interrupted) {
    // The rest of the command line the restart needs: the executables, the
    // launcher and --strict (paths absolute, as the restart may run elsewhere).
    std::string extra;
    for (const auto& e : o.exes) {
      const auto eq = e.find('=');
      extra += " --exe " + ::quoted(e.substr(0, eq + 1) + fs::absolute(e.substr(eq + 1)).string());
    }
    if (o.launcher != "mpirun") extra += " --launcher " + ::quoted(o.launcher);
    if (o.strict) extra += " --strict";
    gather_failures(dir);  // a rank that failed before the interruption
    return report_interrupted(o.cfg_path, o.overrides, extra, dir, rc, wall, cfg);
  }
  return report_failure(cfg, dir, failure, rc, wall);
}

}  // namespace

int main(int argc, char** argv) {
  // Output to a reader that went away (coflow run ... | head) must not end
  // the launcher and leave mpirun without its reader: the run goes on, its
  // lines to the terminal are lost, its files are written.
  signal(SIGPIPE, SIG_IGN);
  CLI::App app{"coflow: partitioned co-simulation of particle-laden flows"};
  app.require_subcommand(1);

  RunOptions o;
  bool markdown = false;

  auto* run_cmd = app.add_subcommand("run", "validate a configuration and run it");
  run_cmd->add_option("config", o.cfg_path, "run configuration (YAML)")->required();
  run_cmd->add_flag("--dry-run", o.dry, "print the launch command and stop");
  run_cmd
      ->add_option("--launcher", o.launcher,
                   "mpirun (default), srun (inside an allocation), or sbatch (submit a batch job that runs srun; "
                   "with --dry-run: print its script)")
      ->check(CLI::IsMember({"mpirun", "srun", "sbatch"}));
  run_cmd->add_option("--restart", o.restart, "restart from a checkpoint directory, or latest (the run's newest)");
  run_cmd->add_option("--set", o.overrides, "override a key: --set fluid.lbm.tau=0.9 (repeatable)");
  run_cmd->add_option("--exe", o.exes, "use your own executable for a component: --exe fluid=PATH");
  run_cmd->add_flag("--strict", o.strict, "refuse to run when the pre-run report has a warning");

  auto* val = app.add_subcommand("validate", "check a configuration and print the resolved one");
  val->add_option("config", o.cfg_path, "run configuration (YAML)")->required();
  val->add_option("--set", o.overrides, "override a key: key.path=value");
  val->add_flag("--strict", o.strict, "exit status 2 when the pre-run report has a warning");

  auto* var = app.add_subcommand("variants", "list solvers, methods and their options");
  var->add_flag("--markdown", markdown, "print the full configuration reference in Markdown");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  }

  if (var->parsed()) {
    print_variants(markdown);
    return 0;
  }

  Config cfg;
  try {
    cfg = coflow::config::parse_config(o.cfg_path, coflow::catalog(), o.overrides);
  } catch (const ConfigError& e) {
    std::cerr << e.what() << std::endl;
    return 2;
  }
  if (val->parsed()) {
    std::cout << "# " << o.cfg_path << ": valid\n" << std::flush;
    const int rc = print_report(cfg, o, "# ", stdout);
    print_last_run_advice(cfg);
    std::cout << YAML::Dump(cfg.resolved) << std::endl;
    return rc;
  }
  try {
    return run(cfg, o);
  } catch (const std::exception& e) {  // the run directory, a foreign checkpoint.yaml, fork or pipe
    std::cerr << "coflow: " << e.what() << std::endl;
    return 1;
  }
}
