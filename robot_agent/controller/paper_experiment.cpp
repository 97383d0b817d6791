#include "robot_agent/controller/paper_experiment.hpp"

#include <optional>

namespace swarmform::controller {
namespace {

class PaperExperiment final : public experiment::Experiment {
 public:
  void init(const Mission&, std::size_t) override {}
  void observe(const experiment::Truth& truth) override {
    if (!truth.shape) return;
    formed_ = formed_ || truth.shape->formation_tick.has_value();
    arrived_ = truth.shape->goal_tick.has_value();  // as it stands: a goal that moves undoes an arrival
  }
  experiment::Result conclude() override {
    experiment::Result r;
    r.outcome = std::string(arrived_ ? kPaperOutcomes[0] : formed_ ? kPaperOutcomes[1] : kPaperOutcomes[2]);
    return r;
  }

 private:
  bool formed_ = false;
  bool arrived_ = false;
};

}  // namespace

std::unique_ptr<experiment::Experiment> make_paper_experiment() {
  return std::make_unique<PaperExperiment>();
}

}  // namespace swarmform::controller
