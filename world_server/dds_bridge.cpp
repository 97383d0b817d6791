#include "world_server/dds_bridge.hpp"

namespace swarmform::server {

WorldFaces::WorldFaces(const dds::DdsSettings& settings, std::size_t robots) {
  const std::uint32_t n = dds::face_count(robots);
  for (std::uint32_t f = 0; f < n; ++f) {
    dds::DdsSettings face = settings;
    face.face = f;
    faces.push_back(std::make_unique<dds::Participant>(face));
  }
}

std::vector<const dds::Participant*> WorldFaces::list() const {
  std::vector<const dds::Participant*> out;
  for (const auto& f : faces) out.push_back(f.get());
  return out;
}

FaceMissions::FaceMissions(const WorldFaces& faces) {
  for (const auto& f : faces.faces) writers_.push_back(std::make_unique<dds::MissionWriter>(*f));
}

void FaceMissions::publish(const dds::MissionAnnouncement& announcement) {
  for (auto& w : writers_) w->publish(announcement);
}

FaceCommands::FaceCommands(const WorldFaces& faces, dds::Waiter& waiter, bool realtime,
                           std::uint32_t accept_ids, std::uint32_t samples_per_window)
    : waiter_(waiter) {
  // Counted, not attached: the world wakes once as many samples are in as it awaits commands, not at each one
  // (dds::Waiter, "Counted arrivals").
  for (std::uint32_t f = 0; f < faces.faces.size(); ++f) {
    readers_.push_back(std::make_unique<dds::CommandReader>(*faces.faces[f], waiter, realtime, accept_ids, f,
                                                            /*count_arrivals=*/true, samples_per_window));
  }
}

std::size_t FaceCommands::take(std::vector<dds::CommandSample>& buf, std::size_t max_samples) {
  const std::uint64_t before = waiter_.arrivals();
  std::size_t n = 0;
  bool drained = true;
  for (auto& r : readers_) {
    if (n >= max_samples) {
      drained = false;
      break;
    }
    const std::size_t room = max_samples - n;
    const std::size_t got = r->take(buf, room, n);
    n += got;
    if (got == room) drained = false;  // maybe more left in this reader
  }
  if (drained) {
    waiter_.drained(before);
  } else {
    waiter_.wake();  // the rest is taken at the next call, as a read condition would stay triggered
  }
  return n;
}

void FaceCommands::take_liveliness_changes(std::vector<dds::CommandReader::LivelinessChange>& out) {
  for (auto& r : readers_) r->take_liveliness_changes(out);
}

std::uint64_t FaceCommands::filtered() const {
  std::uint64_t n = 0;
  for (const auto& r : readers_) n += r->filtered();
  return n;
}

void FaceCommands::set_window(std::uint64_t window) {
  for (auto& r : readers_) r->set_window(window);
}

void FaceCommands::take_budget_drops(std::vector<dds::ReceiveBudget::Drops>& out) {
  for (auto& r : readers_) r->take_budget_drops(out);
}

std::uint64_t FaceCommands::over_budget() const {
  std::uint64_t n = 0;
  for (const auto& r : readers_) n += r->over_budget();
  return n;
}

std::optional<RobotId> FaceCommands::authenticated_robot(std::uint32_t face, dds::PublicationHandle writer) {
  if (face >= readers_.size()) return std::nullopt;
  return readers_[face]->authenticated_robot(writer);
}

bool FaceCommands::matched(std::uint32_t face, dds::PublicationHandle writer) const {
  return face < readers_.size() && readers_[face]->matched(writer);
}

std::optional<dds::RemoteWriter> FaceCommands::remote(std::uint32_t face,
                                                      dds::PublicationHandle writer) const {
  if (face >= readers_.size()) return std::nullopt;
  return readers_[face]->remote(writer);
}

WorldLink::WorldLink(const dds::DdsSettings& settings, std::size_t robot_count, bool realtime,
                     std::uint64_t run_nonce, std::uint32_t samples_per_window)
    : faces(settings, robot_count),
      participant(*faces.faces.front()),
      waiter(participant),
      mission(faces),
      robots(faces.list(), robot_count, realtime),
      commands(faces, waiter, realtime, static_cast<std::uint32_t>(robot_count + dds::kMaxExtraChannels),
               samples_per_window),
      state(participant, run_nonce) {
  robots.set_run_nonce(run_nonce);
}

dds::MissionAnnouncement mission_of(const world::Scenario& scenario, std::uint64_t run_nonce) {
  dds::MissionAnnouncement a;
  a.mission = scenario.mission;
  for (const world::RobotGroup& g : scenario.groups) {
    a.groups.push_back({g.first_id, static_cast<std::uint32_t>(g.count), g.mission});
  }
  a.robots = static_cast<std::uint32_t>(scenario.robots.size());
  a.run_nonce = run_nonce;
  a.realtime = scenario.mode == world::Mode::Realtime;
  return a;
}

void pose_rows(const world::World& world, const std::vector<behaviour::KnownColumns>& known,
               std::vector<dds::RobotPoseRow>& rows) {
  const auto& truth = world.robots();
  rows.resize(truth.size());
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const world::RobotTruth& t = truth[i];
    const std::int32_t label = i < known.size() ? known[i].label_of(t.telemetry) : -1;
    rows[i] = dds::RobotPoseRow{t.id, t.pose, t.alive, t.telemetry.state, label};
  }
}

}  // namespace swarmform::server
