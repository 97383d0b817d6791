// The built-in behaviours' descriptors: what the world checks a scenario against and what the pictures draw.
#include "robot_agent/controller/builtins.hpp"

#include <array>

#include "robot_agent/controller/diffusion.hpp"
#include "robot_agent/controller/paper_controller.hpp"
#include "robot_agent/controller/paper_experiment.hpp"
#include "robot_agent/controller/paper_params.hpp"
#include "robot_agent/controller/paper_telemetry.hpp"
#include "robot_agent/controller/phototaxis.hpp"
#include "robot_agent/controller/random_walk.hpp"
#include "robot_agent/controller/robot_state.hpp"

namespace swarmform::controller {
namespace {

using behaviour::Descriptor;
using behaviour::StateSpec;

constexpr std::int32_t state(RobotState s) {
  return static_cast<std::int32_t>(s);
}

// Colours read in order: grey before a label, warm while forming, green when ready, blue in motion, purple at
// the goal.
constexpr std::array kPaperStates = {
    StateSpec{state(RobotState::Idle), "idle", "#9e9e9e"},
    StateSpec{state(RobotState::Searching), "searching", "#ff9800"},
    StateSpec{state(RobotState::Moving), "moving", "#fdd835"},
    StateSpec{state(RobotState::Reached), "reached", "#8bc34a"},
    StateSpec{state(RobotState::Ready), "ready", "#2e7d32"},
    StateSpec{state(RobotState::Motion), "motion", "#1e88e5"},
    StateSpec{state(RobotState::Arrived), "arrived", "#8e24aa"},
};

constexpr std::array kWalkStates = {
    StateSpec{state(RobotState::Idle), "walking", "#1e88e5"},
};

// The random walk's parameters are its class constants (random_walk.hpp): none to set from a scenario.
constexpr std::array<behaviour::ParamSpec, 0> kNoParams{};

std::unique_ptr<Controller> make_paper() {
  return std::make_unique<PaperController>();
}
std::unique_ptr<Controller> make_walk() {
  return std::make_unique<RandomWalk>();
}
std::unique_ptr<Controller> make_diffusion() {
  return std::make_unique<Diffusion>();
}
std::unique_ptr<Controller> make_phototaxis() {
  return std::make_unique<Phototaxis>();
}

const Descriptor kPaper{
    .api_version = behaviour::kApiVersion,
    .name = "paper",
    .summary = "the paper's shape formation from a label matrix, then formation control to the goal",
    .params = kPaperParams,
    .states = kPaperStates,
    .telemetry = kPaperTelemetry,
    .needs_shape = true,
    .needs_goal = true,
    // Label 0 at the robot nearest the origin (its seed election), turned by shape_heading
    // (paper_params.hpp).
    .shape_rules = {.anchor = behaviour::ShapeAnchor::NearestOrigin,
                    .heading_param = "shape_heading",
                    .motion_state = state(RobotState::Motion)},
    .make = &make_paper,
    .sensors = 0,
    // The experiment measures the shape (behaviour/shape_metrics.hpp): its outcome, and the formation and
    // motion numbers as summary.json's own keys (Result::summary), declared by the measurement's table.
    .experiment = {.metrics = {},
                   .summary = shape_metrics::kSummaryFields,
                   .outcomes = kPaperOutcomes,
                   .success = kPaperSuccess,
                   .make = &make_paper_experiment},
};

const Descriptor kWalk{
    .api_version = behaviour::kApiVersion,
    .name = "random_walk",
    .summary = "drive at the speed limit with random turns, turn away from what the ultrasonics see",
    .params = kNoParams,
    .states = kWalkStates,
    .telemetry = {},
    .needs_shape = false,
    .needs_goal = false,
    .shape_rules = {},
    .make = &make_walk,
    .sensors = 0,
    .experiment = {},
};

const Descriptor kDiffusion{
    .api_version = behaviour::kApiVersion,
    .name = "diffusion",
    .summary =
        "drive straight, turn on the spot when the infrared proximity ring sees something ahead (towards "
        "the side where the lidar sees more room), slow down on a dark floor (ground sensors)",
    .params = kNoParams,
    .states = kWalkStates,
    .telemetry = {},
    .needs_shape = false,
    .needs_goal = false,
    .shape_rules = {},
    .make = &make_diffusion,
    .sensors = behaviour::kProximity | behaviour::kGround | behaviour::kLidar,
    .experiment = {},
};

const Descriptor kPhototaxis{
    .api_version = behaviour::kApiVersion,
    .name = "phototaxis",
    .summary =
        "steer towards the light, turn away from what the infrared ring sees ahead, stop on a low battery",
    .params = kNoParams,
    .states = kWalkStates,
    .telemetry = {},
    .needs_shape = false,
    .needs_goal = false,
    .shape_rules = {},
    .make = &make_phototaxis,
    .sensors = behaviour::kLight | behaviour::kProximity | behaviour::kBattery,
    .experiment = {},
};

}  // namespace

const Descriptor& paper_descriptor() {
  return kPaper;
}
const Descriptor& random_walk_descriptor() {
  return kWalk;
}

void add_builtins(behaviour::Registry& registry) {
  registry.add(kPaper);
  registry.add(kWalk);
  registry.add(kDiffusion);
  registry.add(kPhototaxis);
}

behaviour::Registry& builtin_registry() {
  static behaviour::Registry registry = [] {
    behaviour::Registry r;
    add_builtins(r);
    return r;
  }();
  return registry;
}

std::unique_ptr<Controller> make_controller(const Mission& mission, RobotId self) {
  return builtin_registry().make(mission, self);
}

}  // namespace swarmform::controller
