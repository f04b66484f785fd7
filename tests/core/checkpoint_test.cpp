// SPDX-License-Identifier: AGPL-3.0-or-later
// The one checkpoint format: a checkpoint is resumed only by a run of its kind,
// format version and fingerprint, and every refusal names the file and field.
#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "palpa/core/checkpoint.hpp"
#include "palpa/core/termination.hpp"

namespace palpa {
namespace {

using test::ScratchDir;
using test::throws_error;

TEST(Checkpoint, IsReadBackByARunOfItsKindOnly) {
  ScratchDir dir;
  Json doc = checkpoint_document("fit", "abc");
  doc["guesses"] = Json::object();
  const auto path = dir / "checkpoint.json";
  write_json_file(path, doc);
  const CheckpointExpectation fit{"fit", "abc", "the options differ", "the same options"};
  EXPECT_EQ(read_checkpoint(path, fit), doc);
  EXPECT_TRUE(throws_error([&] { read_checkpoint(path, {"design", {}, {}, {}}); }, ErrorKind::Input,
                           {"checkpoint.json", "field 'kind'", "a checkpoint of a fit run", "a palpa design checkpoint"}));
  EXPECT_TRUE(throws_error([&] { read_checkpoint(path, {"fit", "abd", "the options differ", "the same options"}); },
                           ErrorKind::Input, {"field 'fingerprint'", "the options differ", "the same options"}));
  // A checkpoint of another format version is refused, saying what to do.
  doc["palpa_checkpoint"] = kCheckpointFormat - 1;
  write_json_file(path, doc);
  EXPECT_TRUE(throws_error([&] { read_checkpoint(path, fit); }, ErrorKind::Input,
                           {"field 'palpa_checkpoint'", "an older palpa", "start the run afresh"}));
  // Files of the first format (a member per kind) and other JSON are not checkpoints.
  write_json_file(path, Json{{"palpa_fit_checkpoint", 1}, {"fingerprint", "abc"}});
  EXPECT_TRUE(throws_error([&] { read_checkpoint(path, fit); }, ErrorKind::Input,
                           {"checkpoint.json", "not a palpa checkpoint", "a palpa fit checkpoint"}));
  write_json_file(path, Json::array());
  EXPECT_TRUE(throws_error([&] { read_checkpoint(path, fit); }, ErrorKind::Input, {"not a palpa checkpoint"}));
}

TEST(Termination, NamesRoundTripAndUnknownOnesAreRefused) {
  for (const Termination t : {Termination::Converged, Termination::IterationLimit, Termination::NoProgress,
                              Termination::Failed, Termination::NotRun}) {
    EXPECT_EQ(parse_termination(to_string(t)), t);
  }
  EXPECT_EQ(to_string(Termination::IterationLimit), "iteration_limit");
  EXPECT_TRUE(throws_error([] { parse_termination("done", ErrorContext{"summary.json", 0, 0, "termination"}); },
                           ErrorKind::Input, {"summary.json", "unknown termination 'done'", "iteration_limit"}));
}

}  // namespace
}  // namespace palpa
