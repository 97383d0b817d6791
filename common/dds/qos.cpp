#include "common/dds/qos.hpp"

namespace swarmform::dds {

Qos make_qos(Channel channel) {
  Qos qos;
  dds_qos_t* q = qos.get();
  dds_qset_liveliness(q, DDS_LIVELINESS_AUTOMATIC, kLivelinessLease);
  switch (channel) {
    case Channel::Mission:
      dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
      dds_qset_durability(q, DDS_DURABILITY_TRANSIENT_LOCAL);
      dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 1);
      break;
    case Channel::Sensor:
      dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
      dds_qset_durability(q, DDS_DURABILITY_VOLATILE);
      dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 1);
      break;
    case Channel::Command:
      dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
      dds_qset_durability(q, DDS_DURABILITY_VOLATILE);
      dds_qset_history(q, DDS_HISTORY_KEEP_ALL, 0);
      break;
    case Channel::WorldState:
      dds_qset_reliability(q, DDS_RELIABILITY_BEST_EFFORT, 0);
      dds_qset_durability(q, DDS_DURABILITY_VOLATILE);
      dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 1);
      break;
  }
  return qos;
}

}  // namespace swarmform::dds
