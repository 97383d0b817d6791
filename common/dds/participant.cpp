#include "common/dds/participant.hpp"

#include <string>

#include "common/dds/internal/idl.hpp"
#include "common/dds/internal/topics.hpp"

namespace swarmform::dds {

struct Participant::Impl {
  Entity domain;
  Entity participant;
  Topics topics;
  bool secure = false;
};

namespace {

constexpr const char* kMissionTopic = "sf_mission";
constexpr const char* kSensorTopic = "sf_sensor";
constexpr const char* kCommandTopic = "sf_command";
constexpr const char* kWorldStateTopic = "sf_world_state";
constexpr const char* kObserveTopic = "sf_observe";
constexpr const char* kControlTopic = "sf_control";

Entity make_topic(dds_entity_t participant, const dds_topic_descriptor_t* desc, const char* name) {
  const dds_entity_t topic = dds_create_topic(participant, desc, name, nullptr, nullptr);
  if (topic == DDS_RETCODE_NOT_ALLOWED_BY_SECURITY) {
    throw DdsError(std::string("dds_create_topic(") + name + "): not allowed by this identity's permissions",
                   topic);
  }
  return Entity(topic, "dds_create_topic");
}

}  // namespace

Participant::Participant(const DdsSettings& settings) : impl_(std::make_unique<Impl>()) {
  const std::string xml = cyclone_config_string(settings);
  const auto local_id = static_cast<dds_domainid_t>(local_domain_id(settings));  // a world face's own
  const dds_entity_t domain = dds_create_domain(local_id, xml.c_str());
  if (domain < 0) {
    // The usual cause is a port in use, or a user's configuration Cyclone refused: say which, rather than
    // Cyclone's bare "Error".
    std::string what = "dds_create_domain(domain " + std::to_string(settings.domain);
    if (settings.user) {
      what += "; the configuration of " + settings.user->source +
              " is merged on top of ours: Cyclone's messages above say what it refused; --print-dds-config "
              "shows both";
    }
    if (settings.role == Role::World) {
      what += "; is another world_server on this domain? its port " +
              std::to_string(face_discovery_port(settings.domain, settings.face)) + " may be taken";
    }
    throw DdsError(what + ")", domain);
  }
  impl_->domain = Entity(domain, "dds_create_domain");
  const dds_entity_t participant = dds_create_participant(local_id, nullptr, nullptr);
  if (participant < 0 && settings.security) {
    // Cyclone's security plugins say why on stderr (a certificate of another authority, an expired one,
    // permissions that name another subject or are not signed by the CA): name the files here.
    throw DdsError("dds_create_participant with DDS Security as '" + settings.security->identity +
                       "' (certificate " + settings.security->certificate + ", permissions " +
                       settings.security->permissions + ", governance " + settings.security->governance +
                       "; Cyclone's message above says what it refused)",
                   participant);
  }
  impl_->participant = Entity(participant, "dds_create_participant");
  const dds_entity_t p = impl_->participant.get();
  impl_->topics.participant = p;
  impl_->secure = settings.security.has_value();
}

dds_entity_t Participant::Topics::get(Entity& slot, Which which) const {
  std::lock_guard lock(mutex_);
  if (!slot) {
    switch (which) {
      case kMission:
        slot = make_topic(participant, &sfdds_Mission_desc, kMissionTopic);
        break;
      case kSensor:
        slot = make_topic(participant, &sfdds_SensorPacket_desc, kSensorTopic);
        break;
      case kCommand:
        slot = make_topic(participant, &sfdds_Command_desc, kCommandTopic);
        break;
      case kWorldState:
        slot = make_topic(participant, &sfdds_WorldState_desc, kWorldStateTopic);
        break;
      case kObserve:
        slot = make_topic(participant, &sfdds_ObserveFrame_desc, kObserveTopic);
        break;
      case kControl:
        slot = make_topic(participant, &sfdds_Control_desc, kControlTopic);
        break;
    }
  }
  return slot.get();
}

Participant::~Participant() {
  // Children before the participant, the participant before the domain.
  if (impl_) {
    impl_->topics.reset();
    impl_->participant.reset();
    impl_->domain.reset();
  }
}

dds_entity_t Participant::get() const {
  return impl_->participant.get();
}
const Participant::Topics& Participant::topics() const {
  return impl_->topics;
}
bool Participant::secure() const {
  return impl_->secure;
}

}  // namespace swarmform::dds
