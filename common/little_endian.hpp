// Little-endian loads and stores of fixed-size integers, whatever the host's byte order: the byte layouts
// that travel (the robot message, robot_agent/controller/message.hpp, and a packet's readings blob,
// common/dds/readings_blob.hpp) are little-endian. The caller has checked that the bytes are there. Through
// memcpy on a little-endian host, so each compiles to one move, where a byte loop cost ~3 instructions a byte
// (decoding ~73 neighbours' messages a tick is the controller's hottest path, BENCHMARKS.md).
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace swarmform {

template <class T>
T load_le(const std::uint8_t* p) {
  if constexpr (std::endian::native == std::endian::little) {
    T v;
    std::memcpy(&v, p, sizeof v);
    return v;
  } else {
    std::make_unsigned_t<T> v = 0;
    for (std::size_t i = 0; i < sizeof v; ++i) v |= static_cast<std::make_unsigned_t<T>>(p[i]) << (8 * i);
    return static_cast<T>(v);
  }
}

template <class T>
void store_le(std::uint8_t* p, T value) {
  if constexpr (std::endian::native == std::endian::little) {
    std::memcpy(p, &value, sizeof value);
  } else {
    const auto v = static_cast<std::make_unsigned_t<T>>(value);
    for (std::size_t i = 0; i < sizeof v; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
  }
}

}  // namespace swarmform
