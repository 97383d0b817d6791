#include "world_server/viewer_control.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <utility>

#include "world_server/observe_frame.hpp"

namespace swarmform::server {

namespace {

// How often the world checks that its bound viewer's writer is still matched (a lookup, not per sample).
constexpr dds_duration_t kCheckPeriod = DDS_MSECS(200);
constexpr double kMinRate = 1.0;   // frames a second
constexpr double kMaxRate = 60.0;  // frames a second
constexpr std::uint64_t kMaxSteps = 1000000;

std::string writer_name(dds::PublicationHandle w) {
  return "writer " + std::to_string(w);
}

}  // namespace

ViewerControl::ViewerControl(const dds::Participant& participant, std::uint64_t run_nonce,
                             std::uint64_t token, bool lockstep, bool start_paused,
                             dds::BehaviourView behaviour)
    : behaviour_(std::move(behaviour)),
      observe_(participant, run_nonce),
      control_(participant),
      refusals_("world_server", std::cerr),
      run_nonce_(run_nonce),
      token_(token),
      lockstep_(lockstep),
      paused_(lockstep && start_paused),
      created_(dds_time()) {
  describe_frame(behaviour_, frame_);  // the same for every frame of the run
}

void ViewerControl::poll(dds_time_t now) {
  samples_.clear();
  control_.take(samples_);
  for (const dds::ControlSample& c : samples_) {
    std::string why;
    if (c.wire_version != dds::kWireVersion) {
      why = "wire version " + std::to_string(c.wire_version) + ", this world speaks " +
            std::to_string(dds::kWireVersion);
    } else if (c.run_nonce != run_nonce_) {
      why = "not this run's nonce";
    } else if (bound_ && *bound_ != c.writer) {
      why = "not from this run's viewer (another writer is bound)";
    } else if (!bound_ && c.token != token_) {
      why = "wrong viewer token";
    } else if (c.kind >= dds::kControlKinds) {
      why = "unknown control kind " + std::to_string(c.kind);
    }
    if (!why.empty()) {
      refusals_.refuse(c.writer, writer_name(c.writer), "control", why, now);
      continue;
    }
    if (!bound_) {
      bound_ = c.writer;
      changed_ = true;
      std::cerr << "world_server: viewer bound (" << writer_name(c.writer) << ")\n";
    }
    last_heard_ = now;
    apply(c);
  }
  if (bound_ && now - last_check_ >= kCheckPeriod) {
    last_check_ = now;
    if (now - last_heard_ > kSilence || !control_.writer_alive(*bound_)) {
      std::cerr << "world_server: the viewer went away; the run goes on without pause or speed cap\n";
      bound_.reset();
      paused_ = false;
      steps_left_ = 0;
      speed_cap_ = 0.0;
      changed_ = true;
    }
  }
}

void ViewerControl::apply(const dds::ControlSample& c) {
  switch (static_cast<dds::ControlKind>(c.kind)) {
    case dds::ControlKind::Hello:  // also the viewer's heartbeat (kSilence)
      if (std::isfinite(c.value) && c.value > 0) {
        frame_period_ = static_cast<dds_duration_t>(1e9 / std::clamp(c.value, kMinRate, kMaxRate));
      }
      break;
    case dds::ControlKind::Pause:
      paused_ = lockstep_;
      steps_left_ = 0;
      changed_ = true;
      break;
    case dds::ControlKind::Resume:
      // count > 0: the viewer's own resume, its last page closed while paused (the grace in ms); said here,
      // on the world's console, which the launcher shows.
      if (c.count > 0 && paused_) {
        std::cerr << "world_server: the viewer's last page closed while paused; running on after "
                  << static_cast<double>(c.count) / 1e3 << " s without a page" << std::endl;
      }
      paused_ = false;
      steps_left_ = 0;
      changed_ = true;
      break;
    case dds::ControlKind::Step:
      if (!lockstep_) break;
      paused_ = true;
      steps_left_ = std::min(kMaxSteps, steps_left_ + std::min(c.count, kMaxSteps));
      changed_ = true;
      break;
    case dds::ControlKind::Speed:
      speed_cap_ = std::isfinite(c.value) && c.value > 0 ? std::min(c.value, 1e6) : 0.0;
      changed_ = true;
      break;
    case dds::ControlKind::Kill:
      if (c.count <= 0xffffffffULL) kills_.push_back(static_cast<RobotId>(c.count));
      break;
  }
}

bool ViewerControl::holding(dds_time_t now) {
  if (!lockstep_ || !paused_ || steps_left_ > 0) return false;
  if (!bound_ && now - created_ >= kBindWait) {
    // --view-paused with no viewer: say so once and run.
    std::cerr << "world_server: no viewer bound within " << kBindWait / DDS_NSECS_IN_SEC
              << " s of a paused start; running\n";
    paused_ = false;
    changed_ = true;
    return false;
  }
  return true;
}

void ViewerControl::ticked() {
  if (paused_ && steps_left_ > 0) {
    --steps_left_;
    if (steps_left_ == 0) changed_ = true;
  }
}

dds_time_t ViewerControl::next_round_at(dds_time_t last_round_start) const {
  if (!lockstep_ || speed_cap_ <= 0.0) return 0;
  return last_round_start + static_cast<dds_duration_t>(1e9 / speed_cap_);
}

std::vector<RobotId> ViewerControl::take_kills() {
  std::vector<RobotId> out;
  out.swap(kills_);
  return out;
}

void ViewerControl::offer_frame(const world::World& world, const LatestCommand& latest,
                                const experiment::Formation& formation, dds_time_t now, bool finished) {
  // On a schedule (frame_schedule.hpp), not "a period since the last frame".
  if (!bound_ || (!finished && !changed_ && !schedule_.due(now, frame_period_))) return;
  build_frame(world, latest, formation, behaviour_, frame_);
  frame_.finished = finished;
  frame_.paused = lockstep_ && paused_ && steps_left_ == 0;
  frame_.controllable = lockstep_;
  frame_.speed_cap = speed_cap_;
  observe_.publish(frame_);
  schedule_.sent(now, frame_period_);
  changed_ = false;
}

}  // namespace swarmform::server
