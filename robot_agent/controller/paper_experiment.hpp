// The paper behaviour's experiment (behaviour/experiment.hpp): it judges a run as the paper does — did the
// swarm form the shape, and did the formed shape reach the goal — from the world's own measurement of the
// shape on the true poses (Truth::shape), never from what the robots report.
#pragma once

#include <array>
#include <memory>
#include <string_view>

#include "behaviour/experiment.hpp"

namespace swarmform::controller {

inline constexpr std::array<std::string_view, 3> kPaperOutcomes = {"arrived", "formed_not_arrived",
                                                                   "not_formed"};
inline constexpr std::string_view kPaperSuccess = "arrived";

std::unique_ptr<experiment::Experiment> make_paper_experiment();

}  // namespace swarmform::controller
