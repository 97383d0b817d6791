#include "common/dds/robot_process.hpp"

#include <malloc.h>
#include <sched.h>

namespace swarmform::dds {

bool yield_to_world_on_wakeup() {
  sched_param param{};
  param.sched_priority = 0;  // the only priority SCHED_BATCH takes; no privilege is needed
  return sched_setscheduler(0, SCHED_BATCH, &param) == 0;
}

bool keep_freed_heap() {
  constexpr int kTrimThreshold = 32 << 20;
  return mallopt(M_TRIM_THRESHOLD, kTrimThreshold) == 1;
}

}  // namespace swarmform::dds
