#include "common/dds/matching.hpp"

#include <cstring>
#include <tuple>

#include "common/dds/dds_error.hpp"

namespace swarmform::dds {

bool writer_matched(dds_entity_t writer) {
  dds_publication_matched_status_t st{};
  check(dds_get_publication_matched_status(writer, &st), "dds_get_publication_matched_status");
  return st.current_count > 0;
}

std::optional<ParticipantKey> writer_participant(dds_entity_t reader, dds_instance_handle_t writer) {
  dds_builtintopic_endpoint_t* e = dds_get_matched_publication_data(reader, writer);
  if (e == nullptr) return std::nullopt;
  ParticipantKey key{};
  static_assert(sizeof(e->participant_key.v) == std::tuple_size_v<ParticipantKey>);
  std::memcpy(key.data(), e->participant_key.v, key.size());
  dds_builtintopic_free_endpoint(e);
  return key;
}

std::optional<RemoteWriter> remote_writer(dds_entity_t reader, dds_instance_handle_t writer) {
  dds_builtintopic_endpoint_t* e = dds_get_matched_publication_data(reader, writer);
  if (e == nullptr) return std::nullopt;
  RemoteWriter out;
  static_assert(sizeof(e->key.v) == std::tuple_size_v<decltype(out.guid)>);
  std::memcpy(out.guid.data(), e->key.v, out.guid.size());
  std::memcpy(out.participant.data(), e->participant_key.v, out.participant.size());
  dds_builtintopic_free_endpoint(e);
  return out;
}

}  // namespace swarmform::dds
