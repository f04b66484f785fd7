// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/core/atomic_file.hpp"

#include "palpa/core/interrupt.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <signal.h>
#include <spdlog/spdlog.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <mutex>
#include <set>
#include <string>
#include <system_error>

#include "palpa/core/error.hpp"
#include "palpa/core/input_file.hpp"

namespace palpa {

namespace {
std::filesystem::path temporary_name(const std::filesystem::path& target) {
  static std::atomic<unsigned> counter{0};
  const std::string name =
      fmt::format(".{}.tmp-{}-{}", target.filename().string(), ::getpid(), counter.fetch_add(1));
  return target.parent_path() / name;
}

// True when the open file `fd` is still the file at `path` (not unlinked or
// replaced by the run that held it before).
bool same_inode(int fd, const std::filesystem::path& path) {
  struct stat open_file {};
  struct stat named {};
  return ::fstat(fd, &open_file) == 0 && ::stat(path.c_str(), &named) == 0 && open_file.st_dev == named.st_dev &&
         open_file.st_ino == named.st_ino;
}

// Removes the lock file at `path` if no process holds it; true if it did.
bool remove_unheld_lock(const std::filesystem::path& path) {
  const int fd = ::open(path.c_str(), O_RDWR | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return false;
  bool removed = false;
  if (::flock(fd, LOCK_EX | LOCK_NB) == 0 && same_inode(fd, path)) removed = ::unlink(path.c_str()) == 0;
  ::close(fd);
  return removed;
}

// The pid a lock holder wrote into its lock file (0 if none can be read).
long lock_holder(int fd) {
  char text[32] = {};
  const ssize_t n = ::pread(fd, text, sizeof(text) - 1, 0);
  if (n <= 0) return 0;
  char* end = nullptr;
  const long pid = std::strtol(text, &end, 10);
  return end != text && pid > 0 ? pid : 0;
}

// Takes the exclusive lock on `path` (creating the file), or throws an Input
// error naming `dir` when another run holds it. Returns the descriptor, or −1
// where the file system offers no locks (the run goes on unlocked).
int lock_output_folder(const std::filesystem::path& dir, const std::filesystem::path& path) {
  ErrorContext ctx;
  ctx.file = dir.string();
  // A few tries: the file may be unlinked by its last holder between our open
  // and our lock, and then the lock we got is on a file no one else sees.
  for (int attempt = 0; attempt < 16; ++attempt) {
    const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd < 0) {
      const int err = errno;
      throw_input_error(fmt::format("cannot write into the output folder: {}", std::strerror(err)), ctx,
                        "a folder palpa may write into");
    }
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      const long holder = lock_holder(fd);
      ::close(fd);
      if (err == EWOULDBLOCK) {
        throw_input_error(
            fmt::format("another palpa run{} is writing into this output folder",
                        holder > 0 ? fmt::format(" (process {})", holder) : std::string()),
            ctx, "a folder no other run is using: wait for that run to end, or choose another folder");
      }
      spdlog::warn("{}: the output folder cannot be locked ({}); a second run into it would not be refused",
                   dir.string(), std::strerror(err));
      ::unlink(path.c_str());
      return -1;
    }
    if (same_inode(fd, path)) {
      const std::string pid = fmt::format("{}\n", ::getpid());
      if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, pid.data(), pid.size(), 0) != static_cast<ssize_t>(pid.size())) {
        spdlog::debug("{}: could not record this process in the lock file", path.string());
      }
      return fd;
    }
    ::close(fd);
  }
  throw Error(ErrorKind::Internal, fmt::format("{}: the output folder's lock kept changing hands", dir.string()));
}

// The output folders that keep a journal now (OutputFolder with a lock).
struct Journals {
  std::mutex mutex;
  std::vector<OutputFolder*> folders;
};

Journals& journals() {
  static Journals j;
  return j;
}

void note_written(const std::filesystem::path& file) noexcept {
  try {
    std::error_code ec;
    const std::filesystem::path abs = std::filesystem::absolute(file, ec).lexically_normal();
    if (ec) return;
    Journals& j = journals();
    std::lock_guard lock(j.mutex);
    for (OutputFolder* f : j.folders) f->note_written(abs);
  } catch (...) {
    // See OutputFolder::note_written.
  }
}

// The lines of a journal, in order, without repeats; a line holding a NUL
// byte names no file palpa wrote (the system would read it only up to the
// NUL), and is left out.
std::vector<std::string> journal_lines(const std::filesystem::path& file) {
  std::vector<std::string> lines;
  std::set<std::string> seen;
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line.find('\0') != std::string::npos) continue;
    if (seen.insert(line).second) lines.push_back(line);
  }
  return lines;
}

// Appends `text` to the file at `path` (created if missing), never through a
// link: bookkeeping that a link would carry outside the output folder.
bool append_no_follow(const std::filesystem::path& path, const std::string& text) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) return false;
  const bool ok = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  ::close(fd);
  return ok;
}

// The first link met going down from `dir` along `rel` (`rel`'s last part
// included), or an empty path: a path under an output folder that leads
// elsewhere through a link.
std::filesystem::path first_link_below(const std::filesystem::path& dir, const std::filesystem::path& rel) {
  std::filesystem::path p = dir;
  std::error_code ec;
  for (const auto& part : rel) {
    p /= part;
    if (std::filesystem::is_symlink(std::filesystem::symlink_status(p, ec))) return p;
  }
  return {};
}

}  // namespace

bool is_output_bookkeeping(const std::filesystem::path& name) {
  const std::string n = name.filename().string();
  return n == kOutputLockName || n == kOutputJournalName || n == kPreviousJournalName;
}

namespace {

// Refuses (Input) a folder under an output folder that keeps a journal when
// the way down to it passes a link: what palpa writes there would land
// outside the output folder, beyond its journal and its --overwrite.
void refuse_links_below_output_folders(const std::filesystem::path& dir, const ErrorContext& ctx) {
  std::error_code ec;
  const std::filesystem::path abs = std::filesystem::absolute(dir, ec).lexically_normal();
  if (ec) return;
  Journals& j = journals();
  std::lock_guard lock(j.mutex);
  for (const OutputFolder* f : j.folders) {
    const std::filesystem::path rel = abs.lexically_relative(f->journal_folder());
    if (rel.empty() || *rel.begin() == ".." || rel == ".") continue;
    if (const std::filesystem::path link = first_link_below(f->journal_folder(), rel); !link.empty()) {
      throw_input_error(fmt::format("'{}' in the output folder is a link: the file would be written outside the "
                                    "folder",
                                    link.lexically_relative(f->journal_folder()).string()),
                        ctx, "a real folder inside the output folder (remove the link, or choose another -o)");
    }
  }
}

}  // namespace

void refuse_special_output(const std::filesystem::path& target, const ErrorContext& ctx) {
  std::error_code ec;
  const auto link = std::filesystem::symlink_status(target, ec);
  if (!std::filesystem::exists(link)) return;
  const auto st = std::filesystem::status(target, ec);
  const bool special = std::filesystem::exists(st) && !std::filesystem::is_regular_file(st) &&
                       !std::filesystem::is_directory(st);
  bool into_proc = false;
  if (std::filesystem::is_symlink(link)) {
    const std::filesystem::path to = std::filesystem::read_symlink(target, ec).lexically_normal();
    const auto first = to.is_absolute() ? std::next(to.begin()) : to.end();  // past the root
    into_proc = !ec && first != to.end() && *first == "proc";
  }
  if (special || into_proc) {
    throw_input_error("is a device, a pipe or a stream (or a link to one), not a file palpa may replace", ctx,
                      "a path to a file or folder, which palpa writes whole; to print, leave the option out "
                      "where the command prints without it");
  }
}

namespace {

// The folder an output file goes into, after refusing (Input, naming the
// file) a path that names no file or a folder, a folder that does not exist,
// and a target that is one of the run's inputs.
std::filesystem::path checked_output_folder(const std::filesystem::path& target) {
  ErrorContext ctx;
  ctx.file = target.string();
  if (target.filename().empty()) throw_input_error("output path names no file", ctx, "a file name");
  refuse_special_output(target, ctx);
  const std::filesystem::path dir = target.parent_path().empty() ? "." : target.parent_path();
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) {
    throw_input_error(fmt::format("output folder '{}' does not exist", dir.string()), ctx,
                      "an existing folder (create it first)");
  }
  refuse_overwriting_an_input(target);
  if (std::filesystem::is_directory(target, ec)) throw_input_error("output path is a folder", ctx, "a file name");
  refuse_links_below_output_folders(dir, ctx);
  return dir;
}

}  // namespace

AtomicFile::AtomicFile(std::filesystem::path target, bool binary) : target_(std::move(target)) {
  const std::filesystem::path dir = checked_output_folder(target_);
  ErrorContext ctx;
  ctx.file = target_.string();
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
  note_written(target_);
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

OutputBatch::OutputBatch() {
  static std::atomic<unsigned> counter{0};
  // ".tmp-<pid>-" as in temporary_name(): remove_stale_temporaries() knows it.
  prefix_ = fmt::format(".tmp-{}-b{}.", ::getpid(), counter.fetch_add(1));
}

OutputBatch::~OutputBatch() {
  for (const Staged& s : staged_) {
    std::error_code ec;
    std::filesystem::remove(s.temporary, ec);
    unregister_temporary(s.temporary.string());
  }
}

std::filesystem::path OutputBatch::stage(const std::filesystem::path& target) {
  const std::filesystem::path dir = checked_output_folder(target);
  // A killed run's staged files in the folder go now (once per folder and batch).
  if (std::find(cleaned_.begin(), cleaned_.end(), dir) == cleaned_.end()) {
    remove_stale_temporaries(dir);
    cleaned_.push_back(dir);
  }
  Staged s{target.parent_path() / (prefix_ + target.filename().string()), target};
  register_temporary(s.temporary.string());
  staged_.push_back(s);
  return s.temporary;
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
  for (const Staged& s : staged_) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(s.temporary, ec)) {
      throw Error(ErrorKind::Internal, fmt::format("{}: staged for the batch but never written", s.target.string()));
    }
  }
  for (auto& f : files_) f->commit();
  files_.clear();
  for (const Staged& s : staged_) {
    std::error_code ec;
    std::filesystem::rename(s.temporary, s.target, ec);
    unregister_temporary(s.temporary.string());
    if (ec) {
      ErrorContext ctx;
      ctx.file = s.target.string();
      throw_input_error(fmt::format("cannot replace the file: {}", ec.message()), ctx);
    }
    note_written(s.target);
  }
  staged_.clear();
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
  if (dir.empty()) throw_input_error("an empty path", ctx, "a folder for the outputs");
  if (std::filesystem::is_symlink(std::filesystem::symlink_status(dir, ec))) {
    throw_input_error("is a link to nothing", ctx, "a folder for the outputs (remove the link, or create its target)");
  }
  for (std::filesystem::path up = dir.parent_path(); !up.empty() && up != up.parent_path(); up = up.parent_path()) {
    if (std::filesystem::exists(up, ec) && !std::filesystem::is_directory(up, ec)) {
      throw_input_error(fmt::format("cannot create the folder: '{}' is a file, not a folder", up.string()), ctx,
                        "a folder for the outputs");
    }
  }
  std::filesystem::create_directories(dir, ec);
  if (ec) throw_input_error(fmt::format("cannot create the folder: {}", ec.message()), ctx);
}

void require_empty_output(const std::filesystem::path& out, std::string_view resumable, std::string_view option) {
  // What a killed run left half-written does not count, nor the lock of a run
  // still writing there (OutputFolder refuses that one by name), nor the
  // journals of the outputs of earlier runs.
  remove_stale_temporaries(out);
  std::error_code ec;
  bool empty = true;
  if (std::filesystem::is_directory(out, ec)) {
    for (const auto& e : std::filesystem::directory_iterator(out, ec)) {
      if (!is_output_bookkeeping(e.path())) empty = false;
    }
  }
  if (!empty) {
    throw_input_error(fmt::format("output folder '{}' is not empty", out.string()),
                      ErrorContext{out.string(), 0, 0, fmt::format("option {}", option)},
                      resumable.empty()
                          ? std::string("a new or empty folder, or --overwrite")
                          : fmt::format("a new or empty folder, --resume to continue an interrupted {} there, or "
                                        "--overwrite",
                                        resumable));
  }
}

std::size_t remove_stale_temporaries(const std::filesystem::path& dir) {
  std::size_t removed = 0;
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return 0;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.size() < 2 || name[0] != '.') continue;
    if (name == kOutputLockName) {
      if (remove_unheld_lock(e.path())) ++removed;
      continue;
    }
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

OutputFolder::OutputFolder(const std::filesystem::path& dir, OnFailure policy, Lock lock, Start start)
    : policy_(policy) {
  std::error_code ec;
  for (std::filesystem::path p = std::filesystem::absolute(dir, ec).lexically_normal();
       !p.empty() && !std::filesystem::exists(p, ec); p = p.parent_path()) {
    created_.push_back(p);
    if (p == p.parent_path()) break;
  }
  ensure_directory(dir);
  remove_stale_temporaries(dir);
  if (lock == Lock::Exclusive) {
    try {
      // palpa's own bookkeeping is never followed through a link.
      for (const char* name : {kOutputLockName, kOutputJournalName, kPreviousJournalName}) {
        if (std::filesystem::is_symlink(std::filesystem::symlink_status(dir / name, ec))) {
          throw_input_error("is a link, where palpa keeps its own bookkeeping file", in_file((dir / name).string()),
                            "no file of that name, or the one palpa wrote (remove the link)");
        }
      }
      lock_path_ = dir / kOutputLockName;
      lock_fd_ = lock_output_folder(dir, lock_path_);
    } catch (...) {
      remove_created();
      throw;
    }
  }
  if (lock == Lock::Exclusive) {
    dir_ = std::filesystem::absolute(dir, ec).lexically_normal();
    const auto journal = dir / kOutputJournalName;
    const auto previous = dir / kPreviousJournalName;
    if (start == Start::Fresh && std::filesystem::exists(journal, ec)) {
      // A run that neither finished nor was resumed set a journal aside
      // already: its files and those of the run before it are both stale.
      if (std::filesystem::exists(previous, ec)) {
        std::string lines;
        for (const std::string& line : journal_lines(journal)) lines += line + '\n';
        append_no_follow(previous, lines);
        std::filesystem::remove(journal, ec);
      } else {
        std::filesystem::rename(journal, previous, ec);
      }
    }
    Journals& j = journals();
    std::lock_guard guard(j.mutex);
    j.folders.push_back(this);
  }
  tidy_handle_ = register_forced_exit_tidy([this] {
    if (keep_) return;
    unlock();
    remove_created();
  });
}

OutputFolder::~OutputFolder() {
  unregister_forced_exit_tidy(tidy_handle_);
  if (!dir_.empty()) {
    Journals& j = journals();
    std::lock_guard guard(j.mutex);
    j.folders.erase(std::remove(j.folders.begin(), j.folders.end(), this), j.folders.end());
  }
  unlock();
  if (!keep_) remove_created();
}

void OutputFolder::keep() noexcept {
  keep_ = true;
  if (dir_.empty()) return;
  try {
    remove_previous_outputs();
  } catch (const std::exception& e) {
    spdlog::warn("{}: the previous run's outputs could not all be removed: {}", dir_.string(), e.what());
  }
}

void OutputFolder::note_written(const std::filesystem::path& file) noexcept {
  if (dir_.empty()) return;
  try {
    const std::filesystem::path rel = file.lexically_relative(dir_);
    if (rel.empty() || *rel.begin() == ".." || is_output_bookkeeping(rel)) return;
    append_no_follow(dir_ / kOutputJournalName, rel.generic_string() + '\n');
    written_.push_back(file);
  } catch (...) {
    // Bookkeeping only: a file missing from the journal is at worst not
    // cleared by a later --overwrite.
  }
}

std::size_t OutputFolder::written_count() const {
  Journals& j = journals();
  std::lock_guard guard(j.mutex);
  return written_.size();
}

void OutputFolder::remove_written_since(std::size_t count) noexcept {
  Journals& j = journals();
  std::lock_guard guard(j.mutex);
  std::error_code ec;
  for (std::size_t i = count; i < written_.size(); ++i) std::filesystem::remove(written_[i], ec);
  if (count < written_.size()) written_.resize(count);
}

void OutputFolder::remove_previous_outputs() {
  const auto previous = dir_ / kPreviousJournalName;
  std::error_code ec;
  if (!std::filesystem::exists(previous, ec)) return;
  // This run's files, however a hand-edited line spells them ("./a", "b/../a").
  std::set<std::filesystem::path> written;
  for (const std::string& line : journal_lines(dir_ / kOutputJournalName)) {
    written.insert(std::filesystem::path(line).lexically_normal());
  }
  std::size_t removed = 0;
  for (const std::string& line : journal_lines(previous)) {
    const std::filesystem::path rel = std::filesystem::path(line).lexically_normal();
    if (written.count(rel) != 0) continue;
    // A hand-edited journal names nothing outside the folder.
    if (rel.is_absolute() || rel.empty() || *rel.begin() == ".." || is_output_bookkeeping(rel)) continue;
    const std::filesystem::path p = dir_ / rel;
    // ... nor, through a link on the way down, a file outside it.
    if (!first_link_below(dir_, rel).empty()) continue;
    if (!std::filesystem::is_regular_file(std::filesystem::symlink_status(p, ec))) continue;
    try {
      refuse_overwriting_an_input(p);  // one of this run's inputs stays
    } catch (const Error&) {
      continue;
    }
    if (!std::filesystem::remove(p, ec)) continue;
    ++removed;
    // Folders the previous run's files leave empty go too (not the output folder).
    for (auto up = p.parent_path(); up != dir_ && up.string().size() > dir_.string().size();
         up = up.parent_path()) {
      if (!std::filesystem::is_empty(up, ec) || !std::filesystem::remove(up, ec)) break;
    }
  }
  std::filesystem::remove(previous, ec);
  if (removed > 0) {
    spdlog::info("{}: removed {} file{} of the previous run that this run did not write", dir_.string(), removed,
                 removed == 1 ? "" : "s");
  }
}

void OutputFolder::unlock() noexcept {
  if (lock_fd_ < 0) return;
  ::unlink(lock_path_.c_str());  // while still held: no other run can take the lock on it now
  ::close(lock_fd_);
  lock_fd_ = -1;
}

void OutputFolder::remove_created() noexcept {
  std::error_code ec;
  if (policy_ == OnFailure::Wipe && !created_.empty()) std::filesystem::remove_all(created_.front(), ec);
  for (const auto& p : created_) {
    if (!std::filesystem::exists(p, ec)) continue;
    if (!std::filesystem::is_directory(p, ec)) break;
    // A folder this run made that holds nothing but its journal goes too.
    bool only_bookkeeping = true;
    for (auto it = std::filesystem::directory_iterator(p, ec); !ec && it != std::filesystem::directory_iterator();
         it.increment(ec)) {
      if (!is_output_bookkeeping(it->path().filename()) || !it->is_regular_file(ec)) only_bookkeeping = false;
    }
    if (ec || !only_bookkeeping) break;
    for (const char* name : {kOutputJournalName, kPreviousJournalName}) std::filesystem::remove(p / name, ec);
    if (!std::filesystem::remove(p, ec)) break;
  }
}

}  // namespace palpa
