// A plug-in as an older build of the API would leave it: its descriptor says api_version 2. The registry
// reads that first field alone and refuses the plug-in, naming both versions (behaviour_unit_test.cpp).
#include <swarmform/behaviour.hpp>

namespace {

std::unique_ptr<swarmform::controller::Controller> make() {
  return nullptr;
}

const swarmform::behaviour::Descriptor kDescriptor{
    .api_version = 2,
    .name = "old_api",
    .summary = "built against behaviour API version 2",
    .params = {},
    .states = {},
    .telemetry = {},
    .needs_shape = false,
    .needs_goal = false,
    .shape_rules = {},
    .make = &make,
    .sensors = 0,
    .experiment = {},
};

}  // namespace

SWARMFORM_BEHAVIOUR(kDescriptor)
