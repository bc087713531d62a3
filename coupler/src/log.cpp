#include "coflow/log.hpp"

#include <spdlog/sinks/base_sink.h>
#include <spdlog/sinks/basic_file_sink.h>
#include <spdlog/sinks/stdout_sinks.h>

#include <cstdio>
#include <mutex>

namespace coflow::log {

namespace {
std::shared_ptr<spdlog::logger>& instance() {
  static std::shared_ptr<spdlog::logger> logger;
  return logger;
}

// A file opened (for appending: a restart goes on in the same log) at the
// first line it receives, so that a rank with nothing to say leaves no file.
class LazyFileSink final : public spdlog::sinks::base_sink<std::mutex> {
 public:
  explicit LazyFileSink(std::string path) : path_(std::move(path)) {}
  ~LazyFileSink() override {
    if (file_) std::fclose(file_);
  }

 protected:
  void sink_it_(const spdlog::details::log_msg& msg) override {
    if (!file_ && !failed_) {
      file_ = std::fopen(path_.c_str(), "a");
      failed_ = file_ == nullptr;  // the console still has the line, and this one
      if (failed_)
        std::fprintf(stderr, "coflow: cannot open %s: this rank logs to the console only\n", path_.c_str());
    }
    if (!file_) return;
    spdlog::memory_buf_t line;
    formatter_->format(msg, line);
    std::fwrite(line.data(), 1, line.size(), file_);
  }
  void flush_() override {
    if (file_) std::fflush(file_);
  }

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
  bool failed_ = false;
};

std::string file_of(const std::string& dir, const std::string& component, int rank) {
  return rank == 0 ? fmt::format("{}/{}.log", dir, component)
                   : fmt::format("{}/{}.{}.log", dir, component, rank);
}
}  // namespace

void init(const std::string& component, int rank, const std::string& dir) {
  auto console = std::make_shared<spdlog::sinks::stderr_sink_mt>();
  console->set_level(rank == 0 ? spdlog::level::info : spdlog::level::warn);
  std::vector<spdlog::sink_ptr> sinks{console};
  if (!dir.empty()) {
    const std::string path = file_of(dir, component, rank);
    spdlog::sink_ptr f;
    if (rank == 0) {
      f = std::make_shared<spdlog::sinks::basic_file_sink_mt>(path, false);
      f->set_level(spdlog::level::debug);
    } else {
      f = std::make_shared<LazyFileSink>(path);
      f->set_level(spdlog::level::warn);
    }
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
