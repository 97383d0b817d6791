// Entering a named network namespace (`ip netns add NAME`) for the viewer's DDS side only (`--hosts`'s
// `swarm run --hosts` with `--view`): the page's listening socket is made first, in the namespace the viewer
// started in (where the user's browser is), and the DDS participant afterwards, in the world's host.
#pragma once

#include <string>

namespace swarmform::viewer {

// Moves the calling thread into /run/netns/NAME; threads it starts afterwards are created there, sockets
// opened before stay where they were made. Throws std::runtime_error naming the namespace and why (no such
// namespace, not root).
void enter_network_namespace(const std::string& name);

}  // namespace swarmform::viewer
