// `swarm_viewer --replay RUN_DIR` (`swarm view RUN_DIR`): the page and Foxglove over a recording. The server
// holds the timeline (the tick shown, playing or not, the speed): the page scrubs, plays and jumps by sending
// commands, and every frame it is sent goes to Foxglove's subscribers too, so Foxglove follows the same
// timeline. robots.csv is read a tick at a time (robots_csv.hpp): a recording of any size opens at once.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace swarmform::viewer {

struct ReplayOptions {
  std::string run_dir;
  std::string host = "127.0.0.1";
  std::uint16_t port = 8765;
  std::string web_root;
  std::vector<std::string> control_origins;  // WebServerOptions::control_origins
  // `swarm export`: write every recorded tick's Foxglove messages on stdout (Session::export_lines) instead
  // of serving.
  bool export_lines = false;
};

// Serves until SIGINT/SIGTERM. Returns 0; 2 (with a message on stderr naming the file) when the run
// directory's world.json or robots.csv cannot be used. Throws std::runtime_error when the port cannot be
// bound.
int replay(const ReplayOptions& options);

}  // namespace swarmform::viewer
