// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The one checkpoint format of every resumable run (fit, design, sim3d): a
// JSON object, written atomically, that starts
//
//   { "palpa_checkpoint": 2, "kind": "fit", "fingerprint": "…", … }
//
// `palpa_checkpoint` is the format's version, shared by all kinds; `kind` says
// which run wrote it; `fingerprint` identifies the inputs and options the run
// depends on (empty when a run checks them member by member instead). The
// members that follow are the run's own.

#include <filesystem>
#include <string>
#include <string_view>

#include "palpa/core/json.hpp"

namespace palpa {

inline constexpr int kCheckpointFormat = 2;

// The header members of a checkpoint of `kind`; the run adds its own.
Json checkpoint_document(std::string_view kind, std::string_view fingerprint = {});

// What a checkpoint must match to be resumed, and how to say it does not.
struct CheckpointExpectation {
  std::string_view kind;         // "fit", "design", "sim3d"
  std::string_view fingerprint;  // empty: not checked here
  std::string_view differs;      // "the scene differs from the interrupted run's"
  std::string_view same;         // "the same scene file and mesh"
};

// Reads the checkpoint at `path` (as run state: InputUse::RunState). Throws
// palpa::Error (Input) naming the file and field when it is not a checkpoint,
// is one of another kind, of another format version (one written by another
// palpa version cannot be resumed: start afresh), or its fingerprint differs.
Json read_checkpoint(const std::filesystem::path& path, const CheckpointExpectation& expected);

}  // namespace palpa
