// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/core/log.hpp"

#include <spdlog/pattern_formatter.h>
#include <spdlog/sinks/stdout_sinks.h>

namespace palpa {

namespace {
// "%*": the level as a prefix ("warning: "), except for plain information,
// which reads best bare.
class LevelPrefix final : public spdlog::custom_flag_formatter {
 public:
  void format(const spdlog::details::log_msg& msg, const std::tm&,
              spdlog::memory_buf_t& dest) override {
    std::string_view prefix;
    switch (msg.level) {
      case spdlog::level::trace: prefix = "trace: "; break;
      case spdlog::level::debug: prefix = "debug: "; break;
      case spdlog::level::warn: prefix = "warning: "; break;
      case spdlog::level::err:
      case spdlog::level::critical: prefix = "error: "; break;
      default: break;
    }
    dest.append(prefix.data(), prefix.data() + prefix.size());
  }
  std::unique_ptr<custom_flag_formatter> clone() const override {
    return spdlog::details::make_unique<LevelPrefix>();
  }
};
}  // namespace

void configure_logging(Verbosity verbosity) {
  auto logger = spdlog::get("palpa");
  if (!logger) {
    logger = spdlog::stderr_logger_mt("palpa");
    spdlog::set_default_logger(logger);
  }
  // Plain lines for info; the level is spelled out only where it matters.
  auto formatter = std::make_unique<spdlog::pattern_formatter>();
  formatter->add_flag<LevelPrefix>('*').set_pattern("%*%v");
  logger->set_formatter(std::move(formatter));
  switch (verbosity) {
    case Verbosity::Quiet:
      logger->set_level(spdlog::level::warn);
      break;
    case Verbosity::Normal:
      logger->set_level(spdlog::level::info);
      break;
    case Verbosity::Verbose:
      logger->set_level(spdlog::level::debug);
      break;
    case Verbosity::Trace:
      logger->set_level(spdlog::level::trace);
      break;
  }
  logger->flush_on(spdlog::level::info);
}

bool info_enabled() noexcept { return spdlog::default_logger_raw()->should_log(spdlog::level::info); }

}  // namespace palpa
