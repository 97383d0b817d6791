// The seam between the shape formation (paper III.B-C up to 'ready', this folder's allotment, barrier...)
// and the motion phases (III.C 'Ready' to III.E: boundary, leader, parents, eq. 2-7, obstacles).
//
// PaperController (paper_controller.hpp) runs Searching -> Moving -> Reached itself. When the barrier passes
// it calls MotionPhases::on_ready once, then MotionPhases::step every tick for as long as the robot is in
// Ready, Motion or Arrived; the state the step returns is the robot's state. Everything the motion phases
// may read is in FormationContext; they write only the stigmergy (their own namespaces, stigmergy.hpp) and
// what MotionStep returns. Their message section is opaque to us: MotionStep::message is broadcast as the
// RobotMessage's `motion` bytes, and each neighbour's last section is in neighbours.find(id)->message.motion.
//
// make_motion_phases() is defined in motion_factory.cpp; until the motion phases land it returns
// HoldStillMotion (Ready holds still forever).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/shape.hpp"
#include "common/types.hpp"
#include "robot_agent/controller/drive.hpp"
#include "robot_agent/controller/neighbours.hpp"
#include "robot_agent/controller/params.hpp"
#include "robot_agent/controller/robot_state.hpp"
#include "robot_agent/controller/shape_table.hpp"
#include "robot_agent/controller/stigmergy.hpp"

namespace swarmform::controller {

struct FormationContext {
  RobotId self = 0;
  Tick tick = 0;
  const Perception* perception = nullptr;  // this tick's perception (pose, ultrasonics, raw messages)
  Pose2D pose;                             // own pose (positioning sensor), arena frame
  const FormationParams* params = nullptr;
  const ShapeTable* table = nullptr;  // Table II; table->shape() is the matrix
  int label = -1;                     // this robot's label
  Vec2 origin;                        // arena place of label 0
  std::vector<Vec2> places;           // arena place of every label, by label
  double common_heading = 0.0;        // rad, arena frame: the heading every reached robot turned to
  const NeighbourTable* neighbours = nullptr;
  Stigmergy* stigmergy = nullptr;  // shared; write only the motion namespaces (3 and up)
  // The robots in the shape as the barrier saw them when it passed: id -> label (dead ones included until
  // the motion phases find them silent), and the labels no live robot held then (abandoned: a robot died
  // and no spare took its place).
  std::map<RobotId, int> members;
  std::vector<int> abandoned_labels;
  Tick ready_tick = 0;  // tick this robot entered Ready
  // Bumped by the caller whenever `members` or `places` changes; 0 = not tracked (the motion phases then
  // recompute what they derive from them every tick). With them and Stigmergy::revision() the motion phases
  // redo the per-label work (leader, live labels, parent tree) only when an input changed.
  std::uint64_t members_version = 0;
  std::uint64_t places_version = 0;
};

struct MotionStep {
  RobotState state = RobotState::Ready;  // Ready, Motion or Arrived
  Vec2 velocity;                         // desired velocity, arena frame, m/s (turned into wheels by drive)
  std::optional<WheelSpeeds> wheels;     // if set, used as is instead of `velocity` (still clamped)
  std::int32_t parent = -1;              // parent robot's id, -1 none
  bool leader = false;
  double net_force = 0.0;             // |F_net|, eq. (5)
  std::vector<std::uint8_t> message;  // the motion section of this tick's broadcast
  std::vector<std::string> events;    // "<kind> <detail>", see Telemetry::events
};

class MotionPhases {
 public:
  virtual ~MotionPhases() = default;
  // The barrier passed: the robot enters Ready (boundary, leader, parents, eq. 2 reference forces).
  virtual void on_ready(const FormationContext& ctx) = 0;
  // Every tick in Ready, Motion and Arrived, from the tick of on_ready on.
  virtual MotionStep step(const FormationContext& ctx) = 0;
};

// Until the motion phases land: Ready holds still and says nothing of its own.
class HoldStillMotion final : public MotionPhases {
 public:
  void on_ready(const FormationContext&) override {}
  MotionStep step(const FormationContext&) override { return {}; }
};

std::unique_ptr<MotionPhases> make_motion_phases(const FormationParams& params);

}  // namespace swarmform::controller
