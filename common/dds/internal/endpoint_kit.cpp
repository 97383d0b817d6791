#include "common/dds/internal/endpoint_kit.hpp"

#include <cstdio>

#include "common/dds/wire_version.hpp"

namespace swarmform::dds::internal {

Entity make_partitioned(dds_entity_t participant, const std::string& partition, bool publisher) {
  Qos qos;
  dds_qset_partition1(qos.get(), partition.c_str());
  if (publisher) return Entity(dds_create_publisher(participant, qos.get(), nullptr), "dds_create_publisher");
  return Entity(dds_create_subscriber(participant, qos.get(), nullptr), "dds_create_subscriber");
}

Entity make_writer(dds_entity_t parent, dds_entity_t topic, Channel channel, Pace pace) {
  Qos qos = make_qos(channel, pace);
  return Entity(dds_create_writer(parent, topic, qos.get(), nullptr), "dds_create_writer");
}

Entity make_reader(dds_entity_t parent, dds_entity_t topic, Channel channel, const dds_listener_t* listener,
                   Pace pace) {
  Qos qos = make_qos(channel, pace);
  return Entity(dds_create_reader(parent, topic, qos.get(), listener), "dds_create_reader");
}

Entity make_condition(dds_entity_t reader) {
  return Entity(dds_create_readcondition(reader, DDS_ANY_STATE), "dds_create_readcondition");
}

void keep_instance(dds_entity_t writer, const void* key) {
  dds_instance_handle_t handle = 0;
  check(dds_register_instance(writer, &handle, key), "dds_register_instance");
}

std::string version_text(std::uint16_t v) {
  return "wire version " + std::to_string(v) + ", this side speaks " + std::to_string(kWireVersion);
}

std::string nonce_text(std::uint64_t got, std::uint64_t want) {
  char b[96];
  std::snprintf(b, sizeof b, "run nonce %016llx, this side's run is %016llx",
                static_cast<unsigned long long>(got), static_cast<unsigned long long>(want));
  return b;
}

}  // namespace swarmform::dds::internal
