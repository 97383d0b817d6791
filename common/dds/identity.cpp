#include "common/dds/identity.hpp"

namespace swarmform::dds {

std::string to_string(const ParticipantKey& key) {
  static const char* hex = "0123456789abcdef";
  std::string out;
  for (std::uint8_t b : key) {
    out += hex[b >> 4];
    out += hex[b & 15];
  }
  return out;
}

std::string robot_partition(RobotId id) {
  return "robot/" + std::to_string(id);
}

}  // namespace swarmform::dds
