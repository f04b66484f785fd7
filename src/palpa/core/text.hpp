// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Small, strict text helpers shared by every parser: numbers must be numbers,
// the whole token must be consumed, and non-finite values are refused unless the
// caller asks for them.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace palpa {

// Leading/trailing spaces, tabs, CR and LF removed.
std::string_view trim(std::string_view s) noexcept;

// Splits on a single character; empty fields are kept ("a,,b" -> 3 fields).
std::vector<std::string_view> split(std::string_view s, char sep);

// Splits on runs of white space; no empty fields.
std::vector<std::string_view> split_whitespace(std::string_view s);

// Parses the whole of `s` (after trimming) as a double. Returns nullopt for
// anything else: empty text, trailing characters, "nan", "inf", overflow.
std::optional<double> parse_finite_double(std::string_view s) noexcept;

// Parses the whole of `s` as a (possibly negative) 64-bit integer.
std::optional<long long> parse_integer(std::string_view s) noexcept;

// Lower-case ASCII copy.
std::string to_lower(std::string_view s);

// A fingerprint of `text`: 64-bit FNV-1a in 16 hex digits, stable across runs
// and builds (checkpoints use it to recognize their inputs).
std::string fingerprint(std::string_view text);

}  // namespace palpa
