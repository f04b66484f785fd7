// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/core/atomic_file.hpp"

#include "palpa/core/interrupt.hpp"

#include <fmt/format.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <system_error>

#include "palpa/core/error.hpp"

namespace palpa {

namespace {
std::filesystem::path temporary_name(const std::filesystem::path& target) {
  static std::atomic<unsigned> counter{0};
  const std::string name =
      fmt::format(".{}.tmp-{}-{}", target.filename().string(), ::getpid(), counter.fetch_add(1));
  return target.parent_path() / name;
}
}  // namespace

AtomicFile::AtomicFile(std::filesystem::path target, bool binary) : target_(std::move(target)) {
  ErrorContext ctx;
  ctx.file = target_.string();
  if (target_.filename().empty()) {
    throw_input_error("output path names no file", ctx, "a file name");
  }
  const std::filesystem::path dir = target_.parent_path().empty() ? "." : target_.parent_path();
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) {
    throw_input_error(fmt::format("output folder '{}' does not exist", dir.string()), ctx,
                      "an existing folder (create it first)");
  }
  if (std::filesystem::is_directory(target_, ec)) {
    throw_input_error("output path is a folder", ctx, "a file name");
  }
  temp_ = temporary_name(target_);
  register_temporary(temp_.string());
  auto mode = std::ios::out | std::ios::trunc;
  if (binary) mode |= std::ios::binary;
  stream_.open(temp_, mode);
  if (!stream_) {
    throw_input_error(fmt::format("cannot write in '{}': {}", dir.string(), std::strerror(errno)),
                      ctx);
  }
  stream_.exceptions(std::ios::goodbit);
}

AtomicFile::~AtomicFile() { discard(); }

void AtomicFile::commit() {
  if (done_) return;
  stream_.flush();
  const bool ok = stream_.good();
  stream_.close();
  ErrorContext ctx;
  ctx.file = target_.string();
  if (!ok || stream_.fail()) {
    discard();
    throw_input_error("writing failed (disk full or the file system refused it)", ctx);
  }
  std::error_code ec;
  std::filesystem::rename(temp_, target_, ec);
  unregister_temporary(temp_.string());
  if (ec) {
    discard();
    throw_input_error(fmt::format("cannot replace the file: {}", ec.message()), ctx);
  }
  done_ = true;
}

void AtomicFile::discard() noexcept {
  if (done_) return;
  if (stream_.is_open()) stream_.close();
  std::error_code ec;
  std::filesystem::remove(temp_, ec);
  unregister_temporary(temp_.string());
  done_ = true;
}

void write_file_atomic(const std::filesystem::path& target,
                       const std::function<void(std::ostream&)>& write, bool binary) {
  AtomicFile file(target, binary);
  write(file.stream());
  file.commit();
}

std::ostream& OutputBatch::add(const std::filesystem::path& target, bool binary) {
  files_.push_back(std::make_unique<AtomicFile>(target, binary));
  return files_.back()->stream();
}

void OutputBatch::commit() {
  // Check every stream first, so a failure in the last one leaves no earlier
  // file replaced.
  for (auto& f : files_) {
    f->stream().flush();
    if (!f->stream().good()) {
      ErrorContext ctx;
      ctx.file = f->target().string();
      throw_input_error("writing failed (disk full or the file system refused it)", ctx);
    }
  }
  for (auto& f : files_) f->commit();
  files_.clear();
}

void ensure_directory(const std::filesystem::path& dir) {
  ErrorContext ctx;
  ctx.file = dir.string();
  std::error_code ec;
  if (std::filesystem::exists(dir, ec)) {
    if (!std::filesystem::is_directory(dir, ec)) {
      throw_input_error("exists and is not a folder", ctx, "a folder for the outputs");
    }
    return;
  }
  std::filesystem::create_directories(dir, ec);
  if (ec) throw_input_error(fmt::format("cannot create the folder: {}", ec.message()), ctx);
}

std::size_t remove_stale_temporaries(const std::filesystem::path& dir) {
  std::size_t removed = 0;
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return 0;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.size() < 2 || name[0] != '.') continue;
    const auto tmp = name.rfind(".tmp-");
    if (tmp == std::string::npos) continue;
    const auto dash = name.find('-', tmp + 5);
    if (dash == std::string::npos) continue;
    const std::string pid_text = name.substr(tmp + 5, dash - tmp - 5);
    if (pid_text.empty() || pid_text.find_first_not_of("0123456789") != std::string::npos) continue;
    const long pid = std::stol(pid_text);
    if (pid == static_cast<long>(::getpid())) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;  // still running (or not ours)
    std::error_code rm;
    if (std::filesystem::remove(e.path(), rm)) ++removed;
  }
  return removed;
}

OutputFolder::OutputFolder(const std::filesystem::path& dir, OnFailure policy) : policy_(policy) {
  std::error_code ec;
  for (std::filesystem::path p = std::filesystem::absolute(dir, ec).lexically_normal();
       !p.empty() && !std::filesystem::exists(p, ec); p = p.parent_path()) {
    created_.push_back(p);
    if (p == p.parent_path()) break;
  }
  ensure_directory(dir);
  remove_stale_temporaries(dir);
}

OutputFolder::~OutputFolder() {
  if (keep_) return;
  std::error_code ec;
  if (policy_ == OnFailure::Wipe && !created_.empty()) std::filesystem::remove_all(created_.front(), ec);
  for (const auto& p : created_) {
    if (!std::filesystem::exists(p, ec)) continue;
    if (!std::filesystem::is_directory(p, ec) || !std::filesystem::is_empty(p, ec)) break;
    std::filesystem::remove(p, ec);
  }
}

}  // namespace palpa
