// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/core/checkpoint.hpp"

#include <fmt/format.h>

#include "palpa/core/input_file.hpp"

namespace palpa {

Json checkpoint_document(std::string_view kind, std::string_view fingerprint) {
  return Json{{"palpa_checkpoint", kCheckpointFormat}, {"kind", std::string(kind)},
              {"fingerprint", std::string(fingerprint)}};
}

Json read_checkpoint(const std::filesystem::path& path, const CheckpointExpectation& expected) {
  Json doc = read_json_file(path, InputUse::RunState);
  const JsonView v(doc, path.string());
  const std::string what = fmt::format("a palpa {} checkpoint", expected.kind);
  if (!v.is_object() || !v.has("palpa_checkpoint")) v.fail("not a palpa checkpoint", what);
  const long long version = v.at("palpa_checkpoint").as_integer();
  if (version != kCheckpointFormat) {
    v.at("palpa_checkpoint")
        .fail(fmt::format("checkpoint format {} was written by {} palpa", version,
                          version < kCheckpointFormat ? "an older" : "a newer"),
              fmt::format("format {} (start the run afresh, without --resume)", kCheckpointFormat));
  }
  const std::string kind = v.at("kind").as_string();
  if (kind != expected.kind) v.at("kind").fail(fmt::format("a checkpoint of a {} run", kind), what);
  if (!expected.fingerprint.empty() && v.at("fingerprint").as_string() != expected.fingerprint) {
    v.at("fingerprint").fail(std::string(expected.differs), std::string(expected.same));
  }
  return doc;
}

}  // namespace palpa
