// The checks an agent makes on the mission it takes off the wire (common/dds/mission_endpoints.cpp
// MissionReader): the world is a process like any other, and a malformed mission must be refused with a clear
// error, never reach the controller. Kept free of DDS so that the fuzzer (tests/fuzz/mission_fuzz.cpp) runs
// it on its own.
#pragma once

#include <string>

#include "common/mission.hpp"

namespace swarmform {

// InputError at `origin` naming the first field that is wrong: the shape (cells >= -1, labels 0..n-1 once
// each, one 8-connected piece), lengths, speeds and rates finite and > 0, the goal finite, its radius finite
// and
// >= 0, every parameter named and finite.
void check_mission(const Mission& mission, const std::string& origin);

}  // namespace swarmform
