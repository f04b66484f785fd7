// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/core/input_file.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>

#include "palpa/core/error.hpp"

namespace palpa {

std::string read_input_file(const std::filesystem::path& path) {
  ErrorContext ctx;
  ctx.file = path.string();
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status)) throw_input_error("file not found", ctx, "an existing file");
  if (std::filesystem::is_directory(status)) throw_input_error("is a folder, not a file", ctx);
  if (!std::filesystem::is_regular_file(status)) {
    throw_input_error("is not a regular file (a device or a pipe, whose end is unknown)", ctx,
                      "a file on disk");
  }
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw_input_error(fmt::format("cannot read its size: {}", ec.message()), ctx);
  if (size > kMaxInputBytes) {
    throw_input_error(fmt::format("{:.3g} GB is larger than palpa reads", static_cast<double>(size) / 1e9), ctx,
                      fmt::format("a file of at most {:.3g} GB", static_cast<double>(kMaxInputBytes) / 1e9));
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw_input_error(fmt::format("cannot open the file: {}", std::strerror(errno)), ctx);
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw_input_error("reading the file failed", ctx);
  return std::move(buffer).str();
}

}  // namespace palpa
