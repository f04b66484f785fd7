// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/core/input_file.hpp"

#include <fmt/format.h>
#include <sys/stat.h>

#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <system_error>
#include <tuple>

#include "palpa/core/error.hpp"

namespace palpa {

namespace {

// A file's identity: the same file under any path, and not a later file that
// happens to reuse its inode.
using FileIdentity = std::tuple<dev_t, ino_t, off_t, std::int64_t, long>;

std::optional<FileIdentity> identity_of(const std::filesystem::path& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return std::nullopt;
  return FileIdentity{st.st_dev, st.st_ino, st.st_size, static_cast<std::int64_t>(st.st_mtim.tv_sec),
                      st.st_mtim.tv_nsec};
}

struct InputRegistry {
  std::atomic<bool> on{false};
  std::mutex mutex;
  std::set<FileIdentity> inputs;
};

InputRegistry& registry() {
  static InputRegistry r;
  return r;
}

}  // namespace

void remember_input(const std::filesystem::path& path) {
  InputRegistry& r = registry();
  if (!r.on) return;
  if (const auto id = identity_of(path)) {
    const std::lock_guard lock(r.mutex);
    r.inputs.insert(*id);
  }
}

void guard_inputs(bool on) {
  InputRegistry& r = registry();
  const std::lock_guard lock(r.mutex);
  r.on = on;
  r.inputs.clear();
}

void refuse_overwriting_an_input(const std::filesystem::path& target) {
  InputRegistry& r = registry();
  if (!r.on) return;
  const auto id = identity_of(target);
  if (!id) return;
  bool input = false;
  {
    const std::lock_guard lock(r.mutex);
    input = r.inputs.count(*id) > 0;
  }
  if (input) {
    ErrorContext ctx;
    ctx.file = target.string();
    throw_input_error("is one of this run's inputs: writing an output there would destroy it", ctx,
                      "an output path that is none of the inputs: another -o path or folder, or the input moved elsewhere");
  }
}

std::string read_input_file(const std::filesystem::path& path, InputUse use) {
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
  if (use == InputUse::Input) remember_input(path);
  return std::move(buffer).str();
}

}  // namespace palpa
