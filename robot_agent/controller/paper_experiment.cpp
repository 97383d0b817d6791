#include "robot_agent/controller/paper_experiment.hpp"

#include "robot_agent/controller/builtins.hpp"

namespace swarmform::controller {

void PaperExperiment::init(const Mission& mission, std::size_t) {
  shape_.emplace(mission, paper_descriptor());
}

void PaperExperiment::observe(const experiment::Truth& truth) {
  shape_->observe(truth);
  last_tick_ = truth.tick;
}

experiment::Result PaperExperiment::conclude() {
  shape_->conclude();
  const shape_metrics::Measures& m = shape_->measures();
  experiment::Result r;
  r.outcome = std::string(m.goal_tick        ? kPaperOutcomes[0]
                          : m.formation_tick ? kPaperOutcomes[1]
                                             : kPaperOutcomes[2]);
  r.summary = shape_metrics::summary_fields(m);
  return r;
}

bool PaperExperiment::done() const {
  const auto& goal = shape_->measures().goal_tick;
  return goal && last_tick_ + 1 >= *goal + kTicksAfterGoal;
}

experiment::Formation PaperExperiment::formation() const {
  const shape_metrics::Measures& m = shape_->measures();
  return {m.formation_tick, m.shape_error_at_formation};
}

std::unique_ptr<experiment::Experiment> make_paper_experiment() {
  return std::make_unique<PaperExperiment>();
}

const shape_metrics::Measures* paper_measures(const experiment::Experiment* e) {
  const auto* paper = dynamic_cast<const PaperExperiment*>(e);
  return paper != nullptr ? &paper->shape().measures() : nullptr;
}

}  // namespace swarmform::controller
