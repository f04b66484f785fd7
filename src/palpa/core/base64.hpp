// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Base64 (RFC 4648, standard alphabet, '=' padding): binary data inside text
// files (VTK's inline arrays, pictures inside a self-contained HTML report).

#include <optional>
#include <string>
#include <string_view>

namespace palpa {

std::string base64_encode(std::string_view bytes);

// Decodes base64, skipping whitespace; padding ends a chunk, so separately
// encoded pieces (as VTK writes a header and its data) decode like one
// stream. nullopt for a character outside the alphabet.
std::optional<std::string> base64_decode(std::string_view text);

}  // namespace palpa
