// Logging through spdlog: every line carries the component and the rank.
// Rank 0 of a component writes logs/<component>.log; every other rank writes
// its warnings and errors, and only those, to logs/<component>.<rank>.log,
// created at its first such line. No two ranks append to one file (appends
// from several hosts to one file on NFS can overwrite each other), and a run
// on many ranks does not repeat each start-up line once per rank.
#pragma once

#include <memory>
#include <string>

#include <spdlog/spdlog.h>

namespace coflow::log {

// Console: warnings and errors from every rank, info from rank 0 only.
// Files (when `dir` is not empty): as above, under `dir`.
void init(const std::string& component, int rank, const std::string& dir = "");
std::shared_ptr<spdlog::logger> get();

template <class... Args>
void info(fmt::format_string<Args...> f, Args&&... args) { get()->info(f, std::forward<Args>(args)...); }
template <class... Args>
void warn(fmt::format_string<Args...> f, Args&&... args) { get()->warn(f, std::forward<Args>(args)...); }
template <class... Args>
void error(fmt::format_string<Args...> f, Args&&... args) { get()->error(f, std::forward<Args>(args)...); }
template <class... Args>
void debug(fmt::format_string<Args...> f, Args&&... args) { get()->debug(f, std::forward<Args>(args)...); }

}  // namespace coflow::log
