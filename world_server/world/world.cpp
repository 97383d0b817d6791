// The world's tick, written once (after ARGoS: act, physics, media, sense):
//
//   apply_command(i, cmd of tick t)   wheel speeds checked and stored, outgoing message queued
//   step():
//     1. act      the stored wheel speeds of every live robot go to the physics (a failed wheel's as 0)
//     2. physics  `substeps` Bullet steps; contact onsets counted
//     3. truth    poses read back into RobotTruth; spatial grid rebuilt
//     4. medium   messages of tick t -> perceptions of tick t+1 (at the new positions); the bytes of each
//                 perception's messages are copied in when it is first read (perception()), or straight
//                 into the caller's buffer (copy_perception()), from `sent` (the outboxes of tick t)
//     5. sense    pose and ultrasonics of every live robot (a failed sensor reads its maximum); with
//                 defer_perceptions(), a robot's ultrasonics are read when its perception is first read;
//                 then the optional sensors the behaviour declares (Descriptor::sensors), never deferred:
//                 the others stay empty and cost nothing
//     6. tick t+1
// Scheduled world faults (faults.hpp) act on the tick they are active at: a wheel on the command of tick t
// (step 1 of the step from t), loss and range on the perceptions of tick t (step 4 of the step to t), a
// sensor on the readings of tick t.
#include "world_server/world/world.hpp"

#include <algorithm>
#include <cmath>

#include "world_server/world/battery.hpp"
#include "world_server/world/geometry.hpp"
#include "world_server/world/ground.hpp"
#include "world_server/world/lidar.hpp"
#include "world_server/world/light.hpp"
#include "world_server/world/medium.hpp"
#include "world_server/world/physics.hpp"
#include "world_server/world/proximity.hpp"
#include "world_server/world/robot_groups.hpp"
#include "world_server/world/spatial_grid.hpp"
#include "world_server/world/ultrasonic.hpp"

namespace swarmform::world {
namespace {

constexpr double kGridCell = 1.0;  // m: a compromise between the medium's 3 m and the sonar's 2.1 m queries

std::uint32_t declared_sensors(const Scenario& s) {
  return sensors_of_run(s);  // every group's: the world equips every robot alike
}

MediumParams medium_params(const Scenario& s) {
  MediumParams p;
  p.comm_range = s.comm_range;
  p.range_noise_sd = s.range_noise_sd;
  p.bearing_noise_sd = s.bearing_noise_sd;
  p.packet_loss = s.packet_loss;
  p.loss_mean_burst = s.packet_loss_mean_burst;
  p.occlusion = s.occlusion;
  return p;
}

}  // namespace

std::string_view to_string(CommandVerdict v) {
  switch (v) {
    case CommandVerdict::Ok:
      return "ok";
    case CommandVerdict::Clamped:
      return "clamped";
    case CommandVerdict::RejectedNonFinite:
      return "rejected_non_finite";
    case CommandVerdict::MessageDropped:
      return "message_dropped";
    case CommandVerdict::DeadRobot:
      return "dead_robot";
    case CommandVerdict::UnknownRobot:
      return "unknown_robot";
  }
  return "unknown";
}

struct World::Impl {
  const Scenario scenario;
  Physics physics;
  Medium medium;
  Ultrasonic ultrasonic;
  Proximity proximity;
  Ground ground;
  LightSensors light;
  Lidar lidar;
  std::optional<Batteries> batteries;  // the scenario's battery model, if any
  std::vector<Pose2D> before_step;     // the poses before the physics step (battery drain)
  const std::uint32_t sensors;         // the behaviour's declared optional sensors (behaviour::Sensor bits)
  SpatialGrid grid;
  Tick tick = 0;

  std::vector<Pose2D> poses;
  std::vector<char> alive;
  std::vector<Outbox> outboxes;     // this tick's messages, written by apply_command
  std::vector<Outbox> sent;         // last tick's, delivered by step(): the bytes perceptions refer to
  std::vector<char> bytes_pending;  // 1: perceptions[i].messages have their readings but not their bytes yet
  bool defer = false;               // defer_perceptions(): gather inboxes and read sonars when read
  bool deferred = false;            // this tick's inboxes are gathered when read (inbox_pending)
  std::vector<char> inbox_pending;  // 1 (deferred ticks): perceptions[i].messages not gathered yet
  std::vector<char> sonar_pending;  // 1: perceptions[i].ultrasonic not read yet (robot i alive at the step)
  std::vector<char> alive_at_step;  // deferred ticks: who was alive when the messages were delivered
  std::vector<std::vector<RabReading>> read_spare;  // per robot: readings perception() parked for reuse
  std::vector<Perception> perceptions;
  std::vector<UltrasonicReading> sonar;
  std::vector<ProximityReading> infrared;
  std::vector<GroundReading> floor_readings;
  std::vector<LightReading> light_readings;
  std::vector<LidarScan> scans;  // swapped with perceptions[i].lidar: two buffers a robot, no allocation
  std::vector<RobotTruth> truth;
  ContactCounts contacts;
  std::vector<Obstacle> obstacles;  // the scenario's, as they stand after this tick's world events
  std::optional<Goal> goal;         // the run's, as it stands after this tick's goal moves
  std::vector<Fault> faults;        // the scenario's world faults (ultrasonic, wheel, loss, range)
  MediumFaults medium_faults;       // this tick's loss and range faults, per robot

  explicit Impl(const Scenario& s)
      : scenario(s),
        physics(scenario),
        medium(medium_params(scenario), present_statics(scenario, scenario.obstacles), scenario.seed),
        ultrasonic(present_statics(scenario, scenario.obstacles), scenario.ultrasonic_noise_sd,
                   scenario.seed),
        proximity(present_statics(scenario, scenario.obstacles), scenario.proximity_noise, scenario.seed),
        ground(scenario.floor, scenario.arena_centre, scenario.arena_width, scenario.arena_height,
               scenario.ground_noise, scenario.seed),
        light(scenario.lights, present_statics(scenario, scenario.obstacles), scenario.light_noise,
              scenario.seed),
        lidar(scenario.lidar, present_statics(scenario, scenario.obstacles), scenario.lidar_noise,
              scenario.seed),
        sensors(declared_sensors(scenario)),
        obstacles(scenario.obstacles),
        goal(goal_at(scenario, 0)) {
    const std::size_t n = scenario.robots.size();
    alive.assign(n, 1);
    outboxes.resize(n);
    sent.resize(n);
    bytes_pending.assign(n, 0);
    inbox_pending.assign(n, 0);
    sonar_pending.assign(n, 0);
    read_spare.resize(n);
    perceptions.resize(n);
    truth.resize(n);
    for (std::size_t i = 0; i < n; ++i) truth[i].id = static_cast<RobotId>(i);
    if (scenario.battery) {
      batteries.emplace(*scenario.battery, n, scenario.tick_rate);
      for (std::size_t i = 0; i < n; ++i) truth[i].battery = batteries->level(i);
    }
    for (const Fault& f : scenario.faults) {
      if (f.in_world()) faults.push_back(f);
    }
    refresh(/*with_medium=*/false);
  }

  // The loss and range faults active at tick t, per robot (none: medium_faults.any false).
  void medium_faults_at(Tick t) {
    MediumFaults& mf = medium_faults;
    mf.any = false;
    for (const Fault& f : faults) {
      if ((f.kind != FaultKind::Loss && f.kind != FaultKind::Range) || !f.active_at(t)) continue;
      if (!mf.any) {
        mf.any = true;
        mf.silent.assign(poses.size(), 0);
        mf.range.assign(poses.size(), scenario.comm_range);
      }
      const std::size_t lo = f.robot ? *f.robot : 0;
      const std::size_t hi = f.robot ? *f.robot + 1 : poses.size();
      for (std::size_t i = lo; i < hi; ++i) {
        if (f.kind == FaultKind::Loss) mf.silent[i] = 1;
        if (f.kind == FaultKind::Range) mf.range[i] = std::min(mf.range[i], f.value);
      }
    }
  }

  // The failed ultrasonic sensors of robot `id` at tick t read their maximum range.
  void sonar_faults(RobotId id, Tick t, UltrasonicReading& reading) const {
    for (const Fault& f : faults) {
      if (f.kind != FaultKind::Ultrasonic || f.robot != id || !f.active_at(t)) continue;
      for (std::size_t k = 0; k < reading.size(); ++k) {
        if (f.part < 0 || static_cast<std::size_t>(f.part) == k) reading[k] = kUltrasonicMaxRange;
      }
    }
  }

  // A deferred reading (sonar_pending): what the step's sense_all and sonar_faults would have written. The
  // poses and the grid it reads stay as the step left them until the next step.
  void sense_now(RobotId id, UltrasonicReading& out) const {
    out = ultrasonic.read(id, poses, grid);
    sonar_faults(id, tick, out);
  }

  // Each live robot's battery pays for the tick that just ran (idle and motion, from before_step to now); one
  // that runs out stops its wheels.
  void drain_batteries() {
    if (!batteries) return;
    for (std::size_t i = 0; i < poses.size(); ++i) {
      if (!alive[i]) continue;
      if (batteries->drain(i, before_step[i], poses[i])) {
        physics.set_wheels(static_cast<RobotId>(i), 0.0, 0.0);
        truth[i].battery_empty_tick = tick;
      }
      truth[i].battery = batteries->level(i);
    }
  }

  // The optional sensors the behaviour declared, for every live robot (step 5).
  void sense_optional() {
    if (sensors & behaviour::kBattery) {
      for (std::size_t i = 0; i < poses.size(); ++i) {
        if (alive[i]) perceptions[i].battery = truth[i].battery;
      }
    }
    if (sensors & behaviour::kProximity) {
      proximity.sense_all(poses, alive, grid, infrared);
      for (std::size_t i = 0; i < poses.size(); ++i) {
        if (alive[i]) perceptions[i].proximity = infrared[i];
      }
    }
    if (sensors & behaviour::kLight) {
      light.sense_all(poses, alive, grid, light_readings);
      for (std::size_t i = 0; i < poses.size(); ++i) {
        if (alive[i]) perceptions[i].light = light_readings[i];
      }
    }
    if (sensors & behaviour::kGround) {
      ground.sense_all(poses, alive, floor_readings);
      for (std::size_t i = 0; i < poses.size(); ++i) {
        if (alive[i]) perceptions[i].ground = floor_readings[i];
      }
    }
    if (sensors & behaviour::kLidar) {
      lidar.sense_all(poses, alive, grid, scans);
      for (std::size_t i = 0; i < poses.size(); ++i) {
        if (alive[i]) std::swap(perceptions[i].lidar, scans[i]);
      }
    }
  }

  // A revived robot's optional sensors, noiseless as its ultrasonics (sense_now).
  void sense_optional_now(RobotId id, Perception& p) const {
    if (sensors & behaviour::kProximity) p.proximity = proximity.read(id, poses, grid);
    if (sensors & behaviour::kGround) p.ground = ground.read(poses[id]);
    if (sensors & behaviour::kLight) p.light = light.read(id, poses, grid);
    if (sensors & behaviour::kBattery) p.battery = truth[id].battery;
    if (sensors & behaviour::kLidar) lidar.read(id, poses, grid, p.lidar);
  }

  // The world events of tick t: the physics' bodies, then what the sensors and the medium see.
  void world_events_at(Tick t) {
    if (!scenario.goal_events.empty()) goal = goal_at(scenario, t);
    if (apply_world_events(obstacles, scenario.world_events, t) == 0) return;
    for (std::size_t k = 0; k < obstacles.size(); ++k) physics.set_obstacle(k, obstacles[k]);
    const std::vector<Obstacle> statics = present_statics(scenario, obstacles);
    medium.set_statics(statics);
    ultrasonic.set_statics(statics);
    proximity.set_statics(statics);
    light.set_statics(statics);
    lidar.set_statics(statics);
  }

  // Steps 3-5 of the tick: truth, grid, (medium), sensors.
  void refresh(bool with_medium) {
    physics.read_poses(poses);
    for (std::size_t i = 0; i < poses.size(); ++i) {
      truth[i].pose = poses[i];
      truth[i].alive = alive[i] != 0;
    }
    if (with_medium) drain_batteries();
    grid.build(poses, kGridCell);
    if (with_medium) {
      // The messages of this tick become `sent` (a swap: no copy), and the outboxes are free for the next.
      std::swap(outboxes, sent);
      for (Outbox& o : outboxes) o.has_message = false;
      medium_faults_at(tick);
      deferred = defer && !medium.random();
      if (deferred) {
        // The inputs gather() reads stay as they are until the next step; kill() and revive() between
        // now and a read do not change who was alive when the messages went out.
        alive_at_step = alive;
        std::fill(inbox_pending.begin(), inbox_pending.end(), 1);  // a dead receiver's gathers to empty
        std::fill(bytes_pending.begin(), bytes_pending.end(), 0);
      } else {
        medium.deliver(poses, alive, sent, grid, perceptions, /*with_bytes=*/false, &medium_faults);
        for (std::size_t i = 0; i < perceptions.size(); ++i)
          bytes_pending[i] = !perceptions[i].messages.empty();
      }
    }
    sense_optional();
    // Deferred only without noise: the noise is drawn in id order over every live robot, in sense_all.
    const bool sonar_deferred = defer && !ultrasonic.noisy();
    if (sonar_deferred) {
      sonar_pending = alive;
    } else {
      ultrasonic.sense_all(poses, alive, grid, sonar);
    }
    for (std::size_t i = 0; i < poses.size(); ++i) {
      Perception& p = perceptions[i];
      p.tick = tick;
      p.pose = poses[i];
      p.goal = goal;
      if (alive[i] && !sonar_deferred) p.ultrasonic = sonar[i];
    }
    if (sonar_deferred) return;  // sense_now applies the sensor faults at the read
    for (const Fault& f : faults) {
      if (f.kind == FaultKind::Ultrasonic && f.active_at(tick) && alive[*f.robot])
        sonar_faults(*f.robot, tick, perceptions[*f.robot].ultrasonic);
    }
  }
};

World::World(const Scenario& scenario) : impl_(std::make_unique<Impl>(scenario)) {}
World::~World() = default;

const Scenario& World::scenario() const {
  return impl_->scenario;
}
Tick World::tick() const {
  return impl_->tick;
}
std::size_t World::robot_count() const {
  return impl_->poses.size();
}
const Perception& World::perception(RobotId id) const {
  Impl& m = *impl_;
  Perception& p = m.perceptions.at(id);
  if (m.sonar_pending[id]) {
    m.sense_now(id, p.ultrasonic);
    m.sonar_pending[id] = 0;
  }
  if (m.inbox_pending[id]) {
    m.medium.gather(id, m.poses, m.alive_at_step, m.sent, m.grid, p.messages, m.read_spare[id],
                    /*with_bytes=*/true, &m.medium_faults);
    m.inbox_pending[id] = 0;
  }
  if (m.bytes_pending[id]) {
    Medium::fill_bytes(p.messages, m.sent);
    m.bytes_pending[id] = 0;
  }
  return p;
}

const Perception& World::optional_sensors(RobotId id) const {
  return impl_->perceptions.at(id);
}

const Perception& World::copy_perception(RobotId id, PerceptionCopy& copy) const {
  const Impl& m = *impl_;
  const Perception& src = m.perceptions.at(id);
  Perception& dst = copy.perception;
  dst.tick = src.tick;
  dst.pose = src.pose;
  dst.proximity = src.proximity;
  dst.light = src.light;
  dst.ground = src.ground;
  dst.lidar = src.lidar;
  dst.battery = src.battery;
  dst.goal = src.goal;
  if (m.sonar_pending[id]) {
    m.sense_now(id, dst.ultrasonic);
  } else {
    dst.ultrasonic = src.ultrasonic;
  }
  if (m.inbox_pending[id]) {
    m.medium.gather(id, m.poses, m.alive_at_step, m.sent, m.grid, dst.messages, copy.spare,
                    /*with_bytes=*/true, &m.medium_faults);
    return dst;
  }
  const std::size_t n = src.messages.size();
  Medium::resize_reusing(dst.messages, n, copy.spare);
  const bool pending = m.bytes_pending[id] != 0;
  for (std::size_t k = 0; k < n; ++k) {
    const RabReading& from = src.messages[k];
    RabReading& to = dst.messages[k];
    to.sender = from.sender;
    to.range = from.range;
    to.bearing = from.bearing;
    const std::vector<std::uint8_t>& bytes = pending ? m.sent[from.sender].data : from.data;
    to.data.assign(bytes.begin(), bytes.end());
  }
  return dst;
}
const std::vector<RobotTruth>& World::robots() const {
  return impl_->truth;
}
ContactCounts World::last_contacts() const {
  return impl_->contacts;
}
void World::defer_perceptions(bool on) {
  impl_->defer = on;
}
bool World::alive(RobotId id) const {
  return id < impl_->alive.size() && impl_->alive[id] != 0;
}

CommandVerdict World::apply_command(RobotId id, const Command& command) {
  Impl& m = *impl_;
  if (id >= m.alive.size()) return CommandVerdict::UnknownRobot;
  if (!m.alive[id]) return CommandVerdict::DeadRobot;
  if (!std::isfinite(command.left_speed) || !std::isfinite(command.right_speed)) {
    m.physics.set_wheels(id, 0.0, 0.0);  // the robot keeps still; its message and telemetry are refused too
    m.outboxes[id].has_message = false;
    return CommandVerdict::RejectedNonFinite;
  }
  CommandVerdict verdict = CommandVerdict::Ok;
  const double limit = m.scenario.mission.max_speed;
  double left = command.left_speed;
  double right = command.right_speed;
  if (std::abs(left) > limit || std::abs(right) > limit) {
    left = std::clamp(left, -limit, limit);
    right = std::clamp(right, -limit, limit);
    verdict = CommandVerdict::Clamped;
  }
  if (m.batteries && m.batteries->empty(id)) left = right = 0.0;  // out of charge: the wheels stay still
  m.physics.set_wheels(id, left, right);
  Outbox& out = m.outboxes[id];
  out.has_message = false;
  if (command.message.size() > m.scenario.mission.max_message_bytes) {
    verdict = CommandVerdict::MessageDropped;  // reported over Clamped: losing data matters more
  } else if (!command.message.empty()) {
    out.has_message = true;
    out.data.assign(command.message.begin(), command.message.end());
    m.truth[id].last_broadcast_tick = m.tick;
  }
  m.truth[id].telemetry = command.telemetry;
  m.truth[id].telemetry_tick = m.tick;
  m.truth[id].leds = command.leds;
  return verdict;
}

void World::step() {
  Impl& m = *impl_;
  for (const Fault& f : m.faults) {
    if (f.kind == FaultKind::Wheel && f.active_at(m.tick)) m.physics.stop_wheel(*f.robot, f.part);
  }
  if (m.batteries) m.before_step = m.poses;
  m.physics.tick_forward();  // acts with the wheel speeds set by apply_command (or kept from before)
  m.contacts.robot_robot = m.physics.onsets_robot_robot();
  m.contacts.robot_obstacle = m.physics.onsets_robot_obstacle();
  ++m.tick;
  m.world_events_at(m.tick);
  m.refresh(/*with_medium=*/true);
}

void World::kill(RobotId id) {
  Impl& m = *impl_;
  if (id >= m.alive.size() || !m.alive[id]) return;
  m.alive[id] = 0;
  m.physics.set_dead(id, true);
  m.outboxes[id].has_message = false;
  m.perceptions[id].messages.clear();
  m.bytes_pending[id] = 0;
  m.inbox_pending[id] = 0;
  m.truth[id].alive = false;
}

void World::revive(RobotId id) {
  Impl& m = *impl_;
  if (id >= m.alive.size() || m.alive[id]) return;
  m.alive[id] = 1;
  m.physics.set_dead(id, false);  // dynamic again where the body stands, wheels zero
  m.outboxes[id].has_message = false;
  m.truth[id].alive = true;
  m.truth[id].telemetry = Telemetry{};
  m.truth[id].leds = {};
  // Its perception for this tick: fresh sensors, no messages (it heard nothing while dead).
  Perception& p = m.perceptions[id];
  p.messages.clear();
  m.bytes_pending[id] = 0;
  m.inbox_pending[id] = 0;
  m.sense_now(id, p.ultrasonic);
  m.sonar_pending[id] = 0;
  m.sense_optional_now(id, p);
}

const std::vector<Obstacle>& World::obstacles() const {
  return impl_->obstacles;
}

const std::optional<Goal>& World::goal() const {
  return impl_->goal;
}

}  // namespace swarmform::world
