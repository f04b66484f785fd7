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

// The bytes of the regular file at `path`. Throws palpa::Error (Input) naming
// the file when it does not exist, is a folder, is not a regular file (a
// device such as /dev/zero, or a pipe: its size is unknown and it may never
// end), is larger than kMaxInputBytes, or cannot be read.
std::string read_input_file(const std::filesystem::path& path);

}  // namespace palpa
