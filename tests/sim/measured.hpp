// The paper experiment's measures of a run the test watches (formation_tick, goal_tick, shape errors...: the
// experiment's, robot_agent/controller/paper_experiment.hpp, not the world's).
#pragma once

#include <stdexcept>

#include "harness/harness.hpp"
#include "robot_agent/controller/paper_experiment.hpp"
#include "world_server/run/run_session.hpp"

namespace swarmform {

inline const shape_metrics::Measures& measured(const world::RunSession& session) {
  const shape_metrics::Measures* m = controller::paper_measures(session.experiment());
  if (m == nullptr) throw std::logic_error("the run has no paper experiment (or it failed)");
  return *m;
}

inline const shape_metrics::Measures& measured(const harness::Harness& h) {
  return measured(h.session());
}

}  // namespace swarmform
