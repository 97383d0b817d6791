// The observers' part of the DDS wire (docs/wire.md "Observers"), in plain types: the frames the world
// publishes for its viewer on sf_observe and the control samples the viewer sends on sf_control.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "common/dds/entity.hpp"
#include "common/dds/identity.hpp"
#include "common/dds/participant.hpp"
#include "common/dds/wire_version.hpp"
#include "common/types.hpp"

namespace swarmform::dds {

struct ObservedRobotRow {
  RobotId id = 0;
  Pose2D pose;
  bool alive = true;
  std::int32_t state = 0;
  std::int32_t label = -1;
  std::int32_t parent = -1;
  bool leader = false;
  double net_force = 0.0;
  std::array<double, kUltrasonicCount> ultrasonic{};  // m, this tick's readings
  std::vector<std::uint32_t> heard;                   // senders heard this tick
  double left_speed = 0.0;                            // m/s, its last command
  double right_speed = 0.0;
  std::uint32_t message_bytes = 0;    // its last broadcast's size
  std::array<Rgb, kLedCount> leds{};  // its LEDs as last commanded (all off: none lit)
  // The optional sensors its behaviour declared, this tick (common/sensor_readings.hpp pack_sensor_readings):
  // the Sensor bits present, then their readings in bit order.
  std::uint32_t equipped = 0;
  std::vector<double> readings;
  // What its controller last reported in its behaviour's own telemetry columns (Telemetry::extra): named by
  // its group's `columns`, or the frame's without groups; empty before it said any.
  std::vector<double> extra;
};

// One state of the current behaviour: its value in Telemetry::state, its name and its colour ("#rrggbb").
struct StateStyleRow {
  std::int32_t value = 0;
  std::string name;
  std::string colour;
};

// A mixed swarm's robot group: its ids, its behaviour and how that behaviour's robots are drawn and listed.
struct ObservedGroupRow {
  std::uint32_t first_id = 0;
  std::uint32_t count = 0;
  std::string behaviour;
  std::vector<StateStyleRow> states;
  std::vector<std::string> columns;  // its behaviour's own telemetry columns: its robots' `extra` names
};

struct ObserveFrameData {
  std::uint64_t run_nonce = 0;
  Tick tick = 0;
  bool finished = false;
  bool paused = false;
  bool controllable = false;  // lockstep: pause and step are honoured
  double speed_cap = 0.0;     // ticks per second, 0 none
  std::uint32_t alive = 0;
  std::int64_t formation_tick = -1;
  double shape_error = -1.0;  // at formation, grid units; negative: not yet
  std::string behaviour;
  std::vector<StateStyleRow> states;
  std::vector<std::string> telemetry_fields;
  std::vector<std::string> columns;  // the behaviour's own telemetry columns: the robots' `extra` names
  std::vector<ObservedGroupRow>
      groups;  // a mixed swarm's groups in id order (their robots' own); empty without
  std::vector<ObservedRobotRow> robots;
  // The names of robot `id`'s `extra`: its group's columns, or the frame's without groups.
  const std::vector<std::string>& columns_of(RobotId id) const;
  // Reader side: when the world wrote it (the sample's source timestamp, dds_time(): ns since the epoch), for
  // the page's lag.
  std::int64_t sent_at = 0;
};

class ObserveWriter {
 public:
  ObserveWriter(const Participant& participant, std::uint64_t run_nonce);
  ~ObserveWriter();
  ObserveWriter(const ObserveWriter&) = delete;
  ObserveWriter& operator=(const ObserveWriter&) = delete;
  void publish(const ObserveFrameData& frame);  // frame.run_nonce is replaced by this writer's

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

class ObserveReader {
 public:
  explicit ObserveReader(const Participant& participant);
  dds_entity_t condition() const { return condition_.get(); }
  // The newest frame of this wire version and run `run_nonce` into `out`; false if none came. Frames of
  // another version or run are counted in refused().
  bool take(std::uint64_t run_nonce, ObserveFrameData& out);
  std::uint64_t refused() const { return refused_; }

 private:
  Entity reader_;
  Entity condition_;
  std::uint64_t refused_ = 0;
};

enum class ControlKind : std::uint8_t {
  Hello = 0,   // binds the viewer; value: frames a second
  Pause = 1,   // lockstep: hold the tick
  Resume = 2,  // lockstep: run on
  Step = 3,    // lockstep: `count` more ticks, then paused
  Speed = 4,   // lockstep: at most `value` ticks a second, 0 none
  Kill = 5,    // SIGKILL agent `count`, as --kill does
};
inline constexpr std::uint8_t kControlKinds = 6;

struct ControlSample {
  std::uint16_t wire_version = kWireVersion;
  std::uint64_t run_nonce = 0;
  std::uint64_t token = 0;
  std::uint64_t seq = 0;
  std::uint8_t kind = 0;  // a ControlKind if < kControlKinds (checked by the world)
  std::uint64_t count = 0;
  double value = 0.0;
  PublicationHandle writer = 0;  // reader side: who sent it
};

class ControlWriter {
 public:
  explicit ControlWriter(const Participant& participant);
  void send(const ControlSample& sample);
  bool matched() const;  // the world's reader is matched

 private:
  Entity writer_;
};

class ControlReader {
 public:
  explicit ControlReader(const Participant& participant);
  dds_entity_t condition() const { return condition_.get(); }
  // Takes what is there (at most 64 samples a call), appended to `out`.
  void take(std::vector<ControlSample>& out);
  // True while `writer` (a publication handle from a sample) is matched and alive.
  bool writer_alive(PublicationHandle writer) const;

 private:
  Entity reader_;
  Entity condition_;
};

}  // namespace swarmform::dds
