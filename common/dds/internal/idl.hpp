// The one includer of the idlc-generated header (idl/swarmform.idl): the files of common/dds that convert
// between the IDL samples and the plain types include this, nothing outside common/dds can (the generated
// header's folder is on swarmform_dds's private include path only). Also the helpers for the IDL's sequences
// and strings that those conversions share.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/dds/wire_version.hpp"
#include "swarmform.h"

namespace swarmform::dds::internal {

static_assert(kWireVersion == sfdds_WIRE_VERSION,
              "kWireVersion (wire_version.hpp) must equal the IDL's WIRE_VERSION");

// An octet sequence that points into `v` (not owned: Cyclone serialises it during dds_write).
template <typename T>
dds_sequence_octet octets(const std::vector<T>& v) {
  static_assert(sizeof(T) == 1);
  dds_sequence_octet s{};
  s._length = s._maximum = static_cast<std::uint32_t>(v.size());
  s._buffer = const_cast<std::uint8_t*>(reinterpret_cast<const std::uint8_t*>(v.data()));
  s._release = false;
  return s;
}

inline void assign_octets(std::vector<std::uint8_t>& out, const dds_sequence_octet& s) {
  out.assign(s._buffer, s._buffer + s._length);
}

// An IDL string as a std::string (a null one is empty).
inline std::string str(const char* s) {
  return s != nullptr ? std::string(s) : std::string();
}

}  // namespace swarmform::dds::internal
