// The page's messages (viewer/README.md "The page's protocol"), as JSON: a frame of sf_observe and the
// behaviour description of a recording.
#pragma once

#include <nlohmann/json.hpp>

#include "common/dds/observe_wire.hpp"

namespace swarmform::viewer {

nlohmann::json frame_json(const dds::ObserveFrameData& frame);

}  // namespace swarmform::viewer
