#include "world_server/dds_bridge.hpp"

namespace swarmform::server {

WorldLink::WorldLink(const dds::DdsSettings& settings, std::size_t robot_count, bool realtime,
                     std::uint64_t run_nonce)
    : participant(settings),
      waiter(participant),
      mission(participant),
      robots(participant, robot_count, realtime),
      commands(participant, waiter, realtime,
               static_cast<std::uint32_t>(robot_count + dds::kMaxExtraChannels)),
      state(participant, run_nonce) {
  robots.set_run_nonce(run_nonce);
  waiter.attach(commands.condition());
}

dds::MissionAnnouncement mission_of(const world::Scenario& scenario, std::uint64_t run_nonce) {
  dds::MissionAnnouncement a;
  a.mission = scenario.mission;
  a.robots = static_cast<std::uint32_t>(scenario.robots.size());
  a.run_nonce = run_nonce;
  a.realtime = scenario.mode == world::Mode::Realtime;
  return a;
}

void pose_rows(const world::World& world, std::vector<dds::RobotPoseRow>& rows) {
  const auto& truth = world.robots();
  rows.resize(truth.size());
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const world::RobotTruth& t = truth[i];
    rows[i] = dds::RobotPoseRow{t.id, t.pose, t.alive, t.telemetry.state, t.telemetry.label};
  }
}

}  // namespace swarmform::server
