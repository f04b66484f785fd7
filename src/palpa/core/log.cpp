#include "palpa/core/log.hpp"

#include <spdlog/sinks/stdout_sinks.h>

namespace palpa {

void configure_logging(Verbosity verbosity) {
  auto logger = spdlog::get("palpa");
  if (!logger) {
    logger = spdlog::stderr_logger_mt("palpa");
    spdlog::set_default_logger(logger);
  }
  // Plain lines for info; the level is spelled out only where it matters.
  logger->set_pattern("%^%l%$: %v");
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
