// SPDX-License-Identifier: AGPL-3.0-or-later
#include <gtest/gtest.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include "common/test_support.hpp"
#include "palpa/core/atomic_file.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/interrupt.hpp"

namespace palpa {
namespace {

std::string read_all(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(AtomicFile, AppearsOnlyOnCommit) {
  test::ScratchDir dir;
  const auto target = dir / "out.csv";
  {
    AtomicFile f(target);
    f.stream() << "a,b\n1,2\n";
    EXPECT_FALSE(std::filesystem::exists(target));
    EXPECT_EQ(dir.entry_count(), 1u);  // only the temporary
    f.commit();
  }
  EXPECT_EQ(read_all(target), "a,b\n1,2\n");
  EXPECT_EQ(dir.entry_count(), 1u);
}

TEST(AtomicFile, ExceptionLeavesNoFileAndKeepsTheOldOne) {
  test::ScratchDir dir;
  const auto target = dir.write("out.csv", "old\n");
  EXPECT_THROW(write_file_atomic(target,
                                 [](std::ostream& out) {
                                   out << "half";
                                   throw std::runtime_error("crash while writing");
                                 }),
               std::runtime_error);
  EXPECT_EQ(read_all(target), "old\n");
  EXPECT_EQ(dir.entry_count(), 1u);
}

TEST(AtomicFile, MissingFolderIsAnInputError) {
  test::ScratchDir dir;
  EXPECT_TRUE(test::throws_error([&] { AtomicFile f(dir / "nope" / "out.csv"); },
                                 ErrorKind::Input, {"out.csv", "does not exist"}));
}

// A pipe, a device or a link into /proc (/dev/stdout) named as an output is
// refused and stays what it was: palpa would rename a file over it.
TEST(AtomicFile, APipeOrADeviceIsRefusedAndKept) {
  test::ScratchDir dir;
  const auto fifo = dir / "fifo.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::filesystem::create_symlink("/proc/self/fd/1", dir / "stdout.json");
  std::filesystem::create_symlink(fifo, dir / "to-fifo.json");
  for (const auto& target : {fifo, dir / "stdout.json", dir / "to-fifo.json"}) {
    try {
      write_file_atomic(target, [](std::ostream& o) { o << "x"; });
      ADD_FAILURE() << target << " was written";
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::Input);
      EXPECT_NE(std::string(e.what()).find("a device, a pipe or a stream"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(target.filename().string()), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(std::filesystem::is_fifo(fifo));
  EXPECT_TRUE(std::filesystem::is_symlink(dir / "stdout.json"));
  // A device, where one can be read without harm.
  EXPECT_THROW(refuse_special_output("/dev/null", in_file("/dev/null")), Error);
  EXPECT_NO_THROW(refuse_special_output(dir / "new.json", ErrorContext{}));
  EXPECT_NO_THROW(refuse_special_output(dir.path(), ErrorContext{}));
}

TEST(OutputBatch, AllOrNothing) {
  test::ScratchDir dir;
  try {
    OutputBatch batch;
    batch.add(dir / "a.txt") << "a";
    batch.add(dir / "b.txt") << "b";
    throw std::runtime_error("failure before commit");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(dir.entry_count(), 0u);

  OutputBatch batch;
  batch.add(dir / "a.txt") << "a";
  batch.add(dir / "b.txt") << "b";
  batch.commit();
  EXPECT_EQ(read_all(dir / "a.txt"), "a");
  EXPECT_EQ(read_all(dir / "b.txt"), "b");
  EXPECT_EQ(dir.entry_count(), 2u);
}

// A writer that makes its own files writes at the staged names, siblings
// derived from them included; they appear with the batch or not at all, and a
// killed run's staged files are recognized as stale temporaries.
TEST(OutputBatch, StagedFilesAppearWithTheBatchOrNotAtAll) {
  test::ScratchDir dir;
  auto write_trio = [](const std::filesystem::path& node) {  // as a TetGen writer does
    for (const char* ext : {".node", ".ele", ".face"}) {
      std::ofstream(std::filesystem::path(node).replace_extension(ext)) << ext;
    }
  };
  try {
    OutputBatch batch;
    batch.add(dir / "summary.json") << "{}";
    write_trio(batch.stage(dir / "layer.node"));
    batch.stage(dir / "layer.ele");
    batch.stage(dir / "layer.face");
    EXPECT_EQ(dir.entry_count(), 4u);  // three staged files and the summary's temporary
    throw std::runtime_error("failure before commit");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(dir.entry_count(), 0u);

  OutputBatch batch;
  batch.add(dir / "summary.json") << "{}";
  const auto staged = batch.stage(dir / "layer.node");
  EXPECT_EQ(staged.filename().string().rfind(fmt::format(".tmp-{}-", ::getpid()), 0), 0u);
  write_trio(staged);
  batch.stage(dir / "layer.ele");
  batch.stage(dir / "layer.face");
  batch.commit();
  EXPECT_EQ(read_all(dir / "layer.node"), ".node");
  EXPECT_EQ(read_all(dir / "layer.ele"), ".ele");
  EXPECT_EQ(read_all(dir / "layer.face"), ".face");
  EXPECT_EQ(dir.entry_count(), 4u);

  // A staged name that was never written is a defect of the writer, not of the input.
  OutputBatch unwritten;
  unwritten.stage(dir / "other.vtu");
  EXPECT_TRUE(test::throws_error([&] { unwritten.commit(); }, ErrorKind::Internal, {"other.vtu", "never written"}));
}

TEST(EnsureDirectory, CreatesAndRejectsFiles) {
  test::ScratchDir dir;
  ensure_directory(dir / "x" / "y");
  EXPECT_TRUE(std::filesystem::is_directory(dir / "x" / "y"));
  const auto file = dir.write("f", "");
  EXPECT_TRUE(test::throws_error([&] { ensure_directory(file); }, ErrorKind::Input,
                                 {"not a folder"}));
}

// A run killed with SIGKILL cannot remove its temporaries: the next run in
// the folder does, for processes that are gone, and nothing else.
TEST(OutputFolder, RemovesTheTemporariesOfKilledRunsOnly) {
  test::ScratchDir dir;
  const pid_t gone = fork();
  if (gone == 0) _exit(0);
  waitpid(gone, nullptr, 0);  // a pid that no longer runs
  const std::string stale = fmt::format(".summary.json.tmp-{}-0", gone);
  const std::string live = fmt::format(".summary.json.tmp-{}-3", ::getppid());
  const std::string stale_staged = fmt::format(".tmp-{}-b2.layer.node", gone);  // OutputBatch::stage's name
  dir.write(stale, "half");
  dir.write(stale_staged, "half");
  dir.write(live, "in progress");
  dir.write(".hidden", "mine");
  dir.write("summary.json.tmp-1-1", "not a temporary's name");
  EXPECT_EQ(remove_stale_temporaries(dir.path()), 2u);
  EXPECT_FALSE(std::filesystem::exists(dir / stale));
  EXPECT_FALSE(std::filesystem::exists(dir / stale_staged));
  EXPECT_TRUE(std::filesystem::exists(dir / live));
  EXPECT_TRUE(std::filesystem::exists(dir / ".hidden"));
  EXPECT_TRUE(std::filesystem::exists(dir / "summary.json.tmp-1-1"));
  EXPECT_EQ(remove_stale_temporaries(dir / "missing"), 0u);
}

TEST(OutputFolder, AFailedRunLeavesNoEmptyFolderAndKeepsWhatItHolds) {
  test::ScratchDir dir;
  {
    OutputFolder f(dir / "a" / "b");  // dropped without keep(): a failure
    EXPECT_TRUE(std::filesystem::is_directory(dir / "a" / "b"));
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "a"));
  {
    OutputFolder f(dir / "c");
    write_file_atomic(dir / "c" / "checkpoint.json", [](std::ostream& o) { o << "{}"; });
  }
  EXPECT_TRUE(std::filesystem::exists(dir / "c" / "checkpoint.json"));
  {
    OutputFolder f(dir / "d" / "frames", OutputFolder::OnFailure::Wipe);
    write_file_atomic(dir / "d" / "frames" / "f.vtu", [](std::ostream& o) { o << "x"; });
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "d"));
  {
    OutputFolder f(dir / "e");
    f.keep();
  }
  EXPECT_TRUE(std::filesystem::is_directory(dir / "e"));
  // A folder that was there before is never removed, even with Wipe.
  { OutputFolder f(dir / "e", OutputFolder::OnFailure::Wipe); }
  EXPECT_TRUE(std::filesystem::is_directory(dir / "e"));
  const auto file = dir.write("g", "");
  EXPECT_TRUE(test::throws_error([&] { OutputFolder f(file); }, ErrorKind::Input, {"not a folder"}));
  EXPECT_TRUE(std::filesystem::exists(file));
}

// Two runs into one folder: the second is refused while the first holds the
// folder, by name and with the process holding it. A run killed with SIGKILL
// holds nothing any more; its lock file is cleared by the next run.
TEST(OutputFolder, ASecondRunIsRefusedUntilTheFirstEndsHoweverItEnds) {
  test::ScratchDir dir;
  const auto out = dir / "out";
  {
    OutputFolder first(out);
    EXPECT_TRUE(std::filesystem::exists(out / kOutputLockName));
    EXPECT_TRUE(test::throws_error([&] { OutputFolder second(out); }, ErrorKind::Input,
                                   {"another palpa run", fmt::format("(process {})", ::getpid()), "out"}));
    OutputFolder frames(out / "frames", OutputFolder::OnFailure::RemoveIfEmpty, OutputFolder::Lock::None);
    EXPECT_FALSE(std::filesystem::exists(out / "frames" / kOutputLockName));
    first.keep();
  }
  EXPECT_TRUE(std::filesystem::is_directory(out));
  EXPECT_TRUE(std::filesystem::is_empty(out));  // the lock went with the run

  // Another process takes the lock as a run does (raw calls only after fork).
  const std::string lock = (out / kOutputLockName).string();
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t other = fork();
  if (other == 0) {
    const int fd = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0 || ::flock(fd, LOCK_EX) != 0) _exit(1);
    char pid[32];
    const int n = std::snprintf(pid, sizeof(pid), "%d\n", static_cast<int>(::getpid()));
    if (::write(fd, pid, static_cast<std::size_t>(n)) != n || ::write(ready[1], "x", 1) != 1) _exit(1);
    for (;;) ::pause();
  }
  ASSERT_GT(other, 0);
  char byte = 0;
  ASSERT_EQ(::read(ready[0], &byte, 1), 1);
  ::close(ready[0]);
  ::close(ready[1]);
  EXPECT_TRUE(test::throws_error([&] { OutputFolder second(out); }, ErrorKind::Input,
                                 {"another palpa run", fmt::format("(process {})", other)}));
  EXPECT_EQ(remove_stale_temporaries(out), 0u);  // held: stays
  ::kill(other, SIGKILL);
  waitpid(other, nullptr, 0);
  EXPECT_TRUE(std::filesystem::exists(out / kOutputLockName));  // left behind, held by no one
  {
    OutputFolder after(out);
    after.keep();
  }
  EXPECT_FALSE(std::filesystem::exists(out / kOutputLockName));
  dir.write("out/.palpa-lock", "12345\n");
  EXPECT_EQ(remove_stale_temporaries(out), 1u);
  EXPECT_FALSE(std::filesystem::exists(out / kOutputLockName));
}

// A run that the interrupt watchdog ends, inside a step that never checks for
// interrupts, leaves no folder it created: the lock file goes, a folder of
// outputs that only count together goes with its files, and the empty folders
// above it go too; a folder that was there before stays.
TEST(OutputFolder, ARunEndedByTheWatchdogLeavesNoFolderItCreated) {
  test::ScratchDir dir;
  const auto out = dir / "out";
  std::filesystem::create_directories(out);
  const pid_t run = fork();
  if (run == 0) {
    ::alarm(20);  // never hang the suite
    install_interrupt_handlers();
    OutputFolder folder(out / "run" / "deep");
    OutputFolder frames(out / "run" / "deep" / "frames", OutputFolder::OnFailure::Wipe, OutputFolder::Lock::None);
    std::ofstream(out / "run" / "deep" / "frames" / "frame_0001.vtu") << "finished frame";
    ::raise(SIGINT);
    for (;;) ::pause();  // a library call that never returns to a check
  }
  ASSERT_GT(run, 0);
  int status = 0;
  ASSERT_EQ(waitpid(run, &status, 0), run);
  ASSERT_TRUE(WIFEXITED(status)) << "ended by signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
  EXPECT_EQ(WEXITSTATUS(status), 130);
  EXPECT_TRUE(std::filesystem::is_directory(out));
  EXPECT_FALSE(std::filesystem::exists(out / "run")) << "the forced exit left the folders it created";
}

// After --overwrite the folder holds this run's outputs only: what the
// previous run wrote and this one did not goes when this one succeeds (with
// the folders it leaves empty), and not before; a file palpa did not write
// stays. A run that is interrupted and resumed clears the same files.
TEST(OutputFolder, ASucceedingRunRemovesWhatThePreviousRunWroteAndItDidNot) {
  test::ScratchDir dir;
  const auto out = dir / "out";
  const auto write = [&](const std::string& name) {
    std::filesystem::create_directories((out / name).parent_path());
    write_file_atomic(out / name, [&](std::ostream& o) { o << name; });
  };
  {
    OutputFolder first(out);
    for (const char* f : {"summary.json", "frames/body_0001.vtu", "frames/body_0002.vtu", "curves/a.csv"}) write(f);
    first.keep();
  }
  dir.write("out/notes.txt", "the user's own file");
  {
    OutputFolder second(out);
    write("summary.json");
    write("frames/body_0001.vtu");
    // Until the run succeeds, the previous run's outputs stay.
    EXPECT_TRUE(std::filesystem::exists(out / "curves" / "a.csv"));
    second.keep();
  }
  EXPECT_TRUE(std::filesystem::exists(out / "summary.json"));
  EXPECT_TRUE(std::filesystem::exists(out / "frames" / "body_0001.vtu"));
  EXPECT_FALSE(std::filesystem::exists(out / "frames" / "body_0002.vtu"));
  EXPECT_FALSE(std::filesystem::exists(out / "curves")) << "a folder the stale files left empty stays";
  EXPECT_TRUE(std::filesystem::exists(out / "notes.txt"));
  EXPECT_FALSE(std::filesystem::exists(out / kPreviousJournalName));

  // A fresh run that fails, then another fresh one that is interrupted and
  // resumed: the resumed run ends with its own files only.
  {
    OutputFolder failed(out);
    write("frames/body_0009.vtu");
  }
  {
    OutputFolder interrupted(out);
    write("part1.csv");
  }
  {
    OutputFolder resumed(out, OutputFolder::OnFailure::RemoveIfEmpty, OutputFolder::Lock::Exclusive,
                         OutputFolder::Start::Resumed);
    write("part2.csv");
    resumed.keep();
  }
  for (const char* gone : {"summary.json", "frames", "frames/body_0009.vtu"}) {
    EXPECT_FALSE(std::filesystem::exists(out / gone)) << gone;
  }
  for (const char* kept : {"part1.csv", "part2.csv", "notes.txt"}) {
    EXPECT_TRUE(std::filesystem::exists(out / kept)) << kept;
  }
  // A journal edited to name a file outside the folder removes nothing there.
  dir.write("elsewhere.txt", "outside");
  dir.write(std::string("out/") + kOutputJournalName, "../elsewhere.txt\n/etc/hostname\n");
  {
    OutputFolder next(out);
    next.keep();
  }
  EXPECT_TRUE(std::filesystem::exists(dir / "elsewhere.txt"));
}

// A stage of outputs that failed part way takes back what it wrote, and only
// that.
TEST(OutputFolder, AFailedStageTakesBackTheFilesItWrote) {
  test::ScratchDir dir;
  const auto out = dir / "out";
  OutputFolder folder(out);
  write_file_atomic(out / "checkpoint.json", [](std::ostream& o) { o << "{}"; });
  const std::size_t mark = folder.written_count();
  EXPECT_EQ(mark, 1u);
  write_file_atomic(out / "body_before.vtu", [](std::ostream& o) { o << "frame"; });
  write_file_atomic(out / "skin_before.ply", [](std::ostream& o) { o << "ply"; });
  folder.remove_written_since(mark);
  EXPECT_TRUE(std::filesystem::exists(out / "checkpoint.json"));
  EXPECT_FALSE(std::filesystem::exists(out / "body_before.vtu"));
  EXPECT_FALSE(std::filesystem::exists(out / "skin_before.ply"));
  EXPECT_EQ(folder.written_count(), 1u);
  folder.keep();
}

// Nothing palpa removes, appends to or writes under an output folder
// resolves outside it through a link.
TEST(OutputFolder, AJournalLineThroughAFolderLinkRemovesNothingOutside) {
  test::ScratchDir dir;
  const auto out = dir / "out";
  dir.write("elsewhere/precious.txt", "outside");
  std::filesystem::create_directories(out);
  std::filesystem::create_directory_symlink(dir / "elsewhere", out / "linked");
  dir.write(std::string("out/") + kOutputJournalName, "linked/precious.txt\n");
  {
    OutputFolder next(out);
    next.keep();
  }
  EXPECT_EQ(read_all(dir / "elsewhere" / "precious.txt"), "outside");
  EXPECT_TRUE(std::filesystem::is_symlink(out / "linked"));
}

TEST(OutputFolder, BookkeepingFilesThatAreLinksAreRefusedAndTheirTargetsKept) {
  for (const char* name : {kOutputJournalName, kPreviousJournalName, kOutputLockName}) {
    test::ScratchDir dir;
    const auto out = dir / "out";
    dir.write("target.txt", "the user's file\n");
    std::filesystem::create_directories(out);
    std::filesystem::create_symlink(dir / "target.txt", out / name);
    try {
      OutputFolder folder(out);
      write_file_atomic(out / "a.csv", [](std::ostream& o) { o << "1\n"; });
      folder.keep();
      ADD_FAILURE() << name << ": a link for palpa's bookkeeping was taken";
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::Input);
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("is a link"), std::string::npos) << e.what();
    }
    EXPECT_EQ(read_all(dir / "target.txt"), "the user's file\n") << name;
    EXPECT_FALSE(std::filesystem::exists(out / "a.csv")) << name;
  }
}

TEST(OutputFolder, AFolderLinkInsideIsNotWrittenThrough) {
  test::ScratchDir dir;
  const auto out = dir / "out";
  std::filesystem::create_directories(dir / "elsewhere");
  std::filesystem::create_directories(out);
  std::filesystem::create_directory_symlink(dir / "elsewhere", out / "curves");
  OutputFolder folder(out);
  try {
    write_file_atomic(out / "curves" / "a.csv", [](std::ostream& o) { o << "1\n"; });
    ADD_FAILURE() << "written through the link";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Input);
    EXPECT_NE(std::string(e.what()).find("'curves' in the output folder is a link"), std::string::npos) << e.what();
  }
  OutputBatch batch;
  EXPECT_THROW(batch.add(out / "curves" / "b.csv"), Error);
  EXPECT_THROW((void)batch.stage(out / "curves" / "c.vtu"), Error);
  EXPECT_TRUE(std::filesystem::is_empty(dir / "elsewhere"));
  // A folder that is the output folder through a link of the user's own (-o
  // names a link) is written as usual.
  std::filesystem::create_directory_symlink(dir / "elsewhere", dir / "out2");
  OutputFolder through(dir / "out2");
  write_file_atomic(dir / "out2" / "a.csv", [](std::ostream& o) { o << "1\n"; });
  EXPECT_TRUE(std::filesystem::exists(dir / "elsewhere" / "a.csv"));
  through.keep();
  folder.keep();
}

}  // namespace
}  // namespace palpa
