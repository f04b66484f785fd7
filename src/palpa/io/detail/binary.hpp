// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Internal helpers for binary formats (PLY, STL, VTU): values are assembled from
// bytes in an explicit byte order, so files read and write the same on any host.
// Not part of the public API.

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>

namespace palpa::io_detail {

enum class ByteOrder { Little, Big };

template <std::size_t N>
struct UnsignedOfSize;
template <>
struct UnsignedOfSize<1> {
  using type = std::uint8_t;
};
template <>
struct UnsignedOfSize<2> {
  using type = std::uint16_t;
};
template <>
struct UnsignedOfSize<4> {
  using type = std::uint32_t;
};
template <>
struct UnsignedOfSize<8> {
  using type = std::uint64_t;
};

// Reads a T (integer or floating point) from the sizeof(T) bytes at `p`.
template <class T>
T load(const char* p, ByteOrder order) {
  static_assert(std::is_arithmetic_v<T>);
  using U = typename UnsignedOfSize<sizeof(T)>::type;
  U bits = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    const std::size_t k = order == ByteOrder::Little ? i : sizeof(T) - 1 - i;
    const U byte = static_cast<U>(static_cast<unsigned char>(p[k]));
    bits = static_cast<U>(bits | static_cast<U>(byte << (8 * i)));
  }
  return std::bit_cast<T>(bits);
}

// Appends the sizeof(T) bytes of `value` to `out`.
template <class T>
void store(std::string& out, T value, ByteOrder order) {
  static_assert(std::is_arithmetic_v<T>);
  using U = typename UnsignedOfSize<sizeof(T)>::type;
  const U bits = std::bit_cast<U>(value);
  char bytes[sizeof(T)];
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    const std::size_t k = order == ByteOrder::Little ? i : sizeof(T) - 1 - i;
    bytes[k] = static_cast<char>(static_cast<unsigned char>((bits >> (8 * i)) & 0xFFu));
  }
  out.append(bytes, sizeof(T));
}

}  // namespace palpa::io_detail
