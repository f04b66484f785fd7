// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Reading an input file whole, for the readers that parse it from memory.

#include <cstdint>
#include <filesystem>
#include <string>

namespace palpa {

// The largest input file palpa reads whole [bytes]: 4 GiB, well above any
// scan, mesh, log or scene it is meant for.
inline constexpr std::uintmax_t kMaxInputBytes = std::uintmax_t{4} << 30;

// What a file read is to the run: one of its inputs, or state the run itself
// writes again on purpose (a checkpoint, a resumed run's state, a table it
// adds a row to).
enum class InputUse { Input, RunState };

// The bytes of the regular file at `path`. Throws palpa::Error (Input) naming
// the file when it does not exist, is a folder, is not a regular file (a
// device such as /dev/zero, or a pipe: its size is unknown and it may never
// end), is larger than kMaxInputBytes, or cannot be read. An Input is
// remembered for the input guard below.
std::string read_input_file(const std::filesystem::path& path, InputUse use = InputUse::Input);

// The input guard: once on (the command line turns it on for each run),
// every file read as an Input is remembered by its identity (device, inode,
// size, modification time), and an output about to replace one of them is
// refused (AtomicFile), whatever path names it: a side output derived from
// -o, a file in an output folder, a link. Off, nothing is remembered (a test
// program reads and rewrites many files over its life).
void guard_inputs(bool on);

// Remembers `path` for the input guard as a file the run refers to as an
// input without reading it here (the curves a dataset lists).
void remember_input(const std::filesystem::path& path);

// Throws palpa::Error (Input) naming `target` when the guard is on and
// `target` is a file this process read as an input.
void refuse_overwriting_an_input(const std::filesystem::path& target);

}  // namespace palpa
