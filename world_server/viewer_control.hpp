// The world's end of its viewer (docs/wire.md "Observers"): the sf_observe writer and the
// sf_control reader, the binding to the run's own viewer, and what the viewer asked for (frame rate, pause,
// steps, a speed cap, kills). Made only when the launcher gave the world a viewer token (--viewer-token): a
// run without a viewer has no observer endpoint and pays nothing.
//
// Binding: the first control sample with this run's nonce and the token binds its writer (as a claim binds an
// agent's); every later sample from another writer is refused and counted. When the bound writer goes away
// (the viewer died or was closed), the world forgets the pause and the speed cap and runs on: a viewer can
// never stop a run by dying.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "behaviour/experiment.hpp"
#include "common/dds/behaviour_view.hpp"
#include "common/dds/observe_wire.hpp"
#include "common/dds/refusal_log.hpp"
#include "world_server/frame_schedule.hpp"
#include "world_server/observe_frame.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::server {

class ViewerControl {
 public:
  // `lockstep`: pause, step and speed are honoured (realtime ticks on the clock). `start_paused`: hold tick
  // 0 until the viewer says go (or no viewer bound within kBindWait).
  ViewerControl(const dds::Participant& participant, std::uint64_t run_nonce, std::uint64_t token,
                bool lockstep, bool start_paused, dds::BehaviourView behaviour);

  dds_entity_t condition() const { return control_.condition(); }

  // Takes and applies the control samples that came; checks the viewer is still there. Cheap when nothing
  // came. `now`: dds_time().
  void poll(dds_time_t now);
  // True while the world must hold its tick (lockstep, paused and no step left).
  bool holding(dds_time_t now);
  // A round was stepped: one step of a STEP N is used up.
  void ticked();
  // When the next round may begin under the speed cap (0: at once), given when the last one began.
  dds_time_t next_round_at(dds_time_t last_round_start) const;
  // Kills the viewer asked for since the last call (robot ids).
  std::vector<RobotId> take_kills();

  bool bound() const { return bound_.has_value(); }
  // Publishes a frame (observe_frame.hpp) when one is due: a viewer is bound and its rate says so, or the
  // pause state changed (the page must see it at once), or `finished` (the run's last frame).
  void offer_frame(const world::World& world, const LatestCommand& latest,
                   const experiment::Formation& formation, dds_time_t now, bool finished = false);

  static constexpr dds_duration_t kBindWait = DDS_SECS(30);
  // The viewer says HELLO every 250 ms; silent this long, it is gone (a SIGKILLed viewer's writer stays
  // matched until its participant's lease of 30 s lapses). A false alarm (the world's own stall) only drops
  // the pause and the cap; the next HELLO binds the viewer again.
  static constexpr dds_duration_t kSilence = DDS_SECS(2);

 private:
  void apply(const dds::ControlSample& c);

  dds::BehaviourView behaviour_;
  dds::ObserveFrameData frame_;
  dds::ObserveWriter observe_;
  dds::ControlReader control_;
  dds::RefusalLog refusals_;
  std::uint64_t run_nonce_;
  std::uint64_t token_;
  bool lockstep_;
  bool paused_;
  bool changed_ = true;
  std::uint64_t steps_left_ = 0;
  double speed_cap_ = 0.0;  // ticks a second
  dds_duration_t frame_period_ = DDS_MSECS(100);
  FrameSchedule schedule_;
  dds_time_t created_ = 0;
  dds_time_t last_check_ = 0;
  dds_time_t last_heard_ = 0;  // the bound viewer's last sample
  std::optional<dds::PublicationHandle> bound_;
  std::vector<RobotId> kills_;
  std::vector<dds::ControlSample> samples_;
};

}  // namespace swarmform::server
