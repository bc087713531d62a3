#include "coflow/log.hpp"

#include <spdlog/sinks/basic_file_sink.h>
#include <spdlog/sinks/stdout_sinks.h>

namespace coflow::log {

namespace {
std::shared_ptr<spdlog::logger>& instance() {
  static std::shared_ptr<spdlog::logger> logger;
  return logger;
}
}  // namespace

void init(const std::string& component, int rank, const std::string& file) {
  auto console = std::make_shared<spdlog::sinks::stderr_sink_mt>();
  console->set_level(rank == 0 ? spdlog::level::info : spdlog::level::warn);
  std::vector<spdlog::sink_ptr> sinks{console};
  if (!file.empty()) {
    auto f = std::make_shared<spdlog::sinks::basic_file_sink_mt>(file, false);
    f->set_level(spdlog::level::debug);
    sinks.push_back(f);
  }
  auto logger = std::make_shared<spdlog::logger>(component, sinks.begin(), sinks.end());
  logger->set_pattern(fmt::format("[%Y-%m-%d %H:%M:%S.%e] [{}:{}] [%l] %v", component, rank));
  logger->set_level(spdlog::level::debug);
  logger->flush_on(spdlog::level::info);
  instance() = logger;
}

std::shared_ptr<spdlog::logger> get() {
  if (!instance()) init("coflow", 0);
  return instance();
}

}  // namespace coflow::log
