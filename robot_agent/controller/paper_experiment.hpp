// The paper behaviour's experiment (behaviour/experiment.hpp): it judges a run as the paper does — did the
// swarm form the shape, and did the formed shape reach the goal — measuring the shape on the true poses
// (behaviour/shape_metrics.hpp), never from what the robots report. Its measures are summary.json's
// formation_tick, shape_error_at_formation, ..., stuck_robots and the distortion series (Result::summary);
// the view's formation line is its formation tick and shape error then.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string_view>

#include "behaviour/experiment.hpp"
#include "behaviour/shape_metrics.hpp"

namespace swarmform::controller {

inline constexpr std::array<std::string_view, 3> kPaperOutcomes = {"arrived", "formed_not_arrived",
                                                                   "not_formed"};
inline constexpr std::string_view kPaperSuccess = "arrived";
// The run goes on this many ticks after goal_tick, so the recording shows the formation settle at the goal.
inline constexpr Tick kTicksAfterGoal = 20;

class PaperExperiment final : public experiment::Experiment {
 public:
  void init(const Mission& mission, std::size_t robots) override;
  void observe(const experiment::Truth& truth) override;
  experiment::Result conclude() override;
  // True kTicksAfterGoal - 1 ticks after goal_tick: the world ends the run one tick after done.
  bool done() const override;
  experiment::Formation formation() const override;

  // The measurement so far (tests read it); only after init.
  const shape_metrics::ShapeMetrics& shape() const { return *shape_; }

 private:
  std::optional<shape_metrics::ShapeMetrics> shape_;
  Tick last_tick_ = 0;
};

std::unique_ptr<experiment::Experiment> make_paper_experiment();
// The paper experiment's measures so far (for tests that watch a run): null when `e` is not the paper's.
const shape_metrics::Measures* paper_measures(const experiment::Experiment* e);

}  // namespace swarmform::controller
