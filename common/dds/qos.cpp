#include "common/dds/qos.hpp"

namespace swarmform::dds {

Qos make_qos(Channel channel, Pace pace) {
  Qos qos;
  dds_qos_t* q = qos.get();
  // Agents' writers carry the short lease (the world must see a dead agent fast), renewed by what they write
  // (MANUAL_BY_TOPIC, qos.hpp); the world's writers the long one (an agent only needs to notice, eventually,
  // that the world went away). A participant asserts AUTOMATIC liveliness by a reliable message to every
  // peer each (shortest lease of its writers - 0.1 s): 500 ms on the world would be 2.5 messages a second to
  // each of 256 agents and as many acknowledgements back.
  if (channel == Channel::Command) {
    dds_qset_liveliness(q, DDS_LIVELINESS_MANUAL_BY_TOPIC, kLivelinessLease);
  } else {
    dds_qset_liveliness(q, DDS_LIVELINESS_AUTOMATIC, kWorldLivelinessLease);
  }
  const dds_reliability_kind_t per_tick =
      pace == Pace::Realtime ? DDS_RELIABILITY_BEST_EFFORT : DDS_RELIABILITY_RELIABLE;
  switch (channel) {
    case Channel::Mission:
      dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
      dds_qset_durability(q, DDS_DURABILITY_TRANSIENT_LOCAL);
      dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 1);
      break;
    case Channel::Sensor:
      dds_qset_reliability(q, per_tick, DDS_SECS(1));
      dds_qset_durability(q, DDS_DURABILITY_VOLATILE);
      dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 1);
      break;
    case Channel::Command:
      // Reliable in realtime too (qos.hpp): the flow control is what keeps a flood from filling the
      // world's socket buffer, where the kernel drops the honest agents' datagrams with the flood's.
      dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
      dds_qset_durability(q, DDS_DURABILITY_VOLATILE);
      dds_qset_history(q, DDS_HISTORY_KEEP_ALL, 0);
      break;
    case Channel::WorldState:
      dds_qset_reliability(q, DDS_RELIABILITY_BEST_EFFORT, 0);
      dds_qset_durability(q, DDS_DURABILITY_VOLATILE);
      dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 1);
      break;
    case Channel::Observe:
      dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
      dds_qset_durability(q, DDS_DURABILITY_VOLATILE);
      dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 1);
      break;
    case Channel::Control:
      // Keep-last 256, not keep-all: the topic has no key, so a flooding writer could otherwise grow the
      // world's reader without bound; a viewer sends a few samples a second.
      dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
      dds_qset_durability(q, DDS_DURABILITY_VOLATILE);
      dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 256);
      break;
  }
  return qos;
}

}  // namespace swarmform::dds
