// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Atomic output. Every file palpa writes goes to a temporary name in the same
// folder and is renamed over the target only when complete, so a crash, an error
// or Ctrl-C never leaves a half-written file. A command that writes several files
// collects them in an OutputBatch and commits them together after all succeeded.

#include <atomic>
#include <cstddef>
#include <filesystem>
#include <string_view>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "palpa/core/error.hpp"

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
  OutputBatch();
  ~OutputBatch();  // removes what was staged unless committed
  OutputBatch(const OutputBatch&) = delete;
  OutputBatch& operator=(const OutputBatch&) = delete;

  std::ostream& add(const std::filesystem::path& target, bool binary = false);
  // For a writer that makes its own files (a mesh, a VTU): where to write
  // `target` for now, a temporary name beside it that ends in its file name,
  // so that a writer deriving siblings from it (a TetGen .node's .ele and
  // .face) writes them where stage() puts those siblings too. commit() renames
  // each over its target. The first stage() into a folder removes the
  // temporaries killed runs left there (remove_stale_temporaries). Throws
  // palpa::Error (Input) as AtomicFile does for a missing folder or a target
  // that is one of the run's inputs.
  std::filesystem::path stage(const std::filesystem::path& target);
  void commit();
  std::size_t size() const noexcept { return files_.size() + staged_.size(); }

 private:
  std::vector<std::unique_ptr<AtomicFile>> files_;
  struct Staged {
    std::filesystem::path temporary, target;
  };
  std::vector<Staged> staged_;
  std::string prefix_;  // of this batch's staged names
  std::vector<std::filesystem::path> cleaned_;  // folders whose stale temporaries are gone
};

// Refuses (palpa::Error, Input, naming `ctx`) an output path that exists as
// something other than a file or a folder — a device (/dev/null), a pipe or a
// socket, also through a link (/dev/stdout) — and a link into /proc: palpa
// replaces its outputs whole, by renaming a file of its own over them.
void refuse_special_output(const std::filesystem::path& target, const ErrorContext& ctx);

// Creates `dir` (and parents) if needed; throws palpa::Error (Input) naming it if
// it exists as a file or cannot be created.
void ensure_directory(const std::filesystem::path& dir);

// The hidden file in an output folder that a running command holds locked.
inline constexpr const char* kOutputLockName = ".palpa-lock";
// The hidden files in an output folder that list what palpa runs wrote there
// (one path per line, relative to the folder): the run's own, and the
// previous run's until the run that replaces it has succeeded.
inline constexpr const char* kOutputJournalName = ".palpa-outputs";
inline constexpr const char* kPreviousJournalName = ".palpa-outputs-previous";

// Whether a file name in an output folder is one of palpa's own bookkeeping
// files (lock, journals), which do not make a folder non-empty.
bool is_output_bookkeeping(const std::filesystem::path& name);

// Removes from `dir` the temporaries that AtomicFile left behind in a process
// that no longer runs (killed with SIGKILL or by the out-of-memory killer:
// ".<name>.tmp-<pid>-<n>" of a pid that is gone) and a folder lock that no run
// holds (kOutputLockName); returns how many. Files of running processes and
// every other file stay.
std::size_t remove_stale_temporaries(const std::filesystem::path& dir);

// Refuses (palpa::Error, Input, naming `option`) an output folder that
// exists and holds anything but bookkeeping and a killed run's temporaries:
// `resumable` ("fit", "design run") names the run that --resume would continue
// there (empty: the command has no --resume).
void require_empty_output(const std::filesystem::path& out, std::string_view resumable = {},
                          std::string_view option = "-o");

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
// A locked folder keeps a journal of the files the run writes under it
// (kOutputJournalName, appended as each AtomicFile is committed). A Fresh run
// sets the previous run's journal aside (kPreviousJournalName); when it
// succeeds (keep()), the files that run wrote and this one did not — frames,
// curves or baselines of a run with other inputs — are removed, so that after
// --overwrite the folder holds this run's outputs only. A Resumed run adds to
// the journal of the run it continues, and clears what that one set aside.
// Files palpa did not write there, and this run's inputs, are never removed.
// A run that the interrupt watchdog ends (interrupt.hpp) is tidied the same
// way: the lock file and the folders it created go as they would on failure.
class OutputFolder {
 public:
  enum class OnFailure { RemoveIfEmpty, Wipe };
  enum class Lock { Exclusive, None };
  enum class Start { Fresh, Resumed };
  explicit OutputFolder(const std::filesystem::path& dir, OnFailure policy = OnFailure::RemoveIfEmpty,
                        Lock lock = Lock::Exclusive, Start start = Start::Fresh);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;
  // The run succeeded: its folders stay, and the previous run's files that it
  // did not write again are removed.
  void keep() noexcept;

  // Adds `file` (absolute, normalized) to the journal if it lies in this folder.
  void note_written(const std::filesystem::path& file) noexcept;
  // The folder whose journal it keeps (absolute, normalized; empty: none).
  const std::filesystem::path& journal_folder() const noexcept { return dir_; }

  // How many files this run has written into the folder so far (a locked
  // folder only), and removing those written since such a count: a stage of
  // outputs that only count together and failed part way (a full disk) takes
  // back what it wrote.
  std::size_t written_count() const;
  void remove_written_since(std::size_t count) noexcept;

 private:
  void remove_created() noexcept;
  void unlock() noexcept;
  void remove_previous_outputs();

  std::vector<std::filesystem::path> created_;  // deepest first
  std::filesystem::path lock_path_;
  std::filesystem::path dir_;  // absolute, normalized; empty: no journal
  std::vector<std::filesystem::path> written_;  // by this process, in order
  int lock_fd_ = -1;
  OnFailure policy_;
  std::atomic<bool> keep_ = false;  // read by the interrupt watchdog's thread too
  std::size_t tidy_handle_ = 0;     // register_forced_exit_tidy
};

}  // namespace palpa
