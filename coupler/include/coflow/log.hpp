// Logging through spdlog: every line carries the component and the rank; one
// log file per component (logs/<component>.log), written by all its ranks.
#pragma once

#include <memory>
#include <string>

#include <spdlog/spdlog.h>

namespace coflow::log {

// Console: warnings and errors from every rank, info from rank 0 only.
// File (when `file` is not empty): everything from every rank.
void init(const std::string& component, int rank, const std::string& file = "");
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
