// faulty: a test plug-in (examples/behaviours/tests) that drives straight on until robot `robot` reaches tick
// `tick`, then fails there: `how` 0 returns a NaN wheel speed, 1 throws, 2 crashes (SIGSEGV). The tests check
// that the failure is a dead robot in robot_agent and a clear end of the run in-process, naming the robot and
// the behaviour.
#include <swarmform/behaviour.hpp>

#include <array>
#include <csignal>
#include <limits>
#include <stdexcept>

namespace {

using namespace swarmform;

constexpr std::array kParams = {
    behaviour::ParamSpec{"robot", 1, 0, 1e6, "the robot that fails"},
    behaviour::ParamSpec{"tick", 20, 0, 1e9, "the tick it fails at"},
    behaviour::ParamSpec{"how", 0, 0, 2, "0: a NaN wheel speed, 1: an exception, 2: a crash (SIGSEGV)"},
};

std::unique_ptr<controller::Controller> make();

const behaviour::Descriptor kDescriptor{
    .name = "faulty",
    .summary = "fails on purpose (tests)",
    .params = kParams,
    .states = {},
    .telemetry = {},
    .needs_shape = false,
    .needs_goal = false,
    .shape_rules = {},
    .make = &make,
    .sensors = 0,
    .experiment = {},
};

class Faulty final : public controller::Controller {
 public:
  void init(const Mission& mission, RobotId self) override {
    fails_ = self == static_cast<RobotId>(behaviour::param(mission, kDescriptor, "robot"));
    tick_ = static_cast<Tick>(behaviour::param(mission, kDescriptor, "tick"));
    how_ = static_cast<int>(behaviour::param(mission, kDescriptor, "how"));
    speed_ = mission.max_speed / 2.0;
  }
  Command step(const Perception& p) override {
    Command c;
    c.left_speed = c.right_speed = speed_;
    if (fails_ && p.tick >= tick_) {
      if (how_ == 1) throw std::runtime_error("faulty: thrown on purpose");
      if (how_ == 2) std::raise(SIGSEGV);  // what a bad pointer does, without the undefined behaviour
      c.left_speed = std::numeric_limits<double>::quiet_NaN();
    }
    return c;
  }
  void reset() override {}

 private:
  bool fails_ = false;
  int how_ = 0;
  Tick tick_ = 0;
  double speed_ = 0.0;
};

std::unique_ptr<controller::Controller> make() {
  return std::make_unique<Faulty>();
}

}  // namespace

SWARMFORM_BEHAVIOUR(kDescriptor)
