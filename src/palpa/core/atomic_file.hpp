// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Atomic output. Every file palpa writes goes to a temporary name in the same
// folder and is renamed over the target only when complete, so a crash, an error
// or Ctrl-C never leaves a half-written file. A command that writes several files
// collects them in an OutputBatch and commits them together after all succeeded.

#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <vector>

namespace palpa {

class AtomicFile {
 public:
  // Opens a temporary file beside `target`. Throws palpa::Error (Input) if the
  // folder does not exist or is not writable.
  explicit AtomicFile(std::filesystem::path target, bool binary = false);
  ~AtomicFile();  // removes the temporary file unless committed
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ostream& stream() { return stream_; }
  const std::filesystem::path& target() const noexcept { return target_; }
  const std::filesystem::path& temporary() const noexcept { return temp_; }

  // Flushes, checks that every write succeeded, and renames over the target.
  void commit();
  // Drops the temporary file (also what the destructor does).
  void discard() noexcept;

 private:
  std::filesystem::path target_;
  std::filesystem::path temp_;
  std::ofstream stream_;
  bool done_ = false;
};

// Writes one file atomically: `write` fills the stream; the file appears only if
// `write` returns normally.
void write_file_atomic(const std::filesystem::path& target,
                       const std::function<void(std::ostream&)>& write, bool binary = false);

// Several outputs that appear together: add() each, fill their streams, then
// commit(). If anything throws before commit(), none of the targets is touched.
class OutputBatch {
 public:
  std::ostream& add(const std::filesystem::path& target, bool binary = false);
  void commit();
  std::size_t size() const noexcept { return files_.size(); }

 private:
  std::vector<std::unique_ptr<AtomicFile>> files_;
};

// Creates `dir` (and parents) if needed; throws palpa::Error (Input) naming it if
// it exists as a file or cannot be created.
void ensure_directory(const std::filesystem::path& dir);

// The hidden file in an output folder that a running command holds locked.
inline constexpr const char* kOutputLockName = ".palpa-lock";

// Removes from `dir` the temporaries that AtomicFile left behind in a process
// that no longer runs (killed with SIGKILL or by the out-of-memory killer:
// ".<name>.tmp-<pid>-<n>" of a pid that is gone) and a folder lock that no run
// holds (kOutputLockName); returns how many. Files of running processes and
// every other file stay.
std::size_t remove_stale_temporaries(const std::filesystem::path& dir);

// An output folder for the length of a run: created (with missing parents) as
// ensure_directory does; if the run ends without keep() — an exception, bad
// input found late — the folders it created are removed again as long as they
// are still empty, so a failed command leaves no empty folder behind.
// Folders that hold a checkpoint or any finished file stay, unless the run
// asks for `Wipe`: then a folder it created goes with whatever it wrote there
// (outputs that only count together, such as a VTU series).
// With Lock::Exclusive (the default) the folder is also locked for the run: a
// second palpa run into the same folder is refused (Input error naming the
// folder and the process holding it) instead of mixing its outputs with this
// one's. The lock is an advisory lock on the hidden file kOutputLockName, which
// the kernel releases when the process ends however it ends; the file itself
// goes when the OutputFolder does. Nested folders of one run take Lock::None.
class OutputFolder {
 public:
  enum class OnFailure { RemoveIfEmpty, Wipe };
  enum class Lock { Exclusive, None };
  explicit OutputFolder(const std::filesystem::path& dir, OnFailure policy = OnFailure::RemoveIfEmpty,
                        Lock lock = Lock::Exclusive);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;
  void keep() noexcept { keep_ = true; }

 private:
  void remove_created() noexcept;

  std::vector<std::filesystem::path> created_;  // deepest first
  std::filesystem::path lock_path_;
  int lock_fd_ = -1;
  OnFailure policy_;
  bool keep_ = false;
};

}  // namespace palpa
