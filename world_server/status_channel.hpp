// The world's machine-readable status: one JSON object per line on a file descriptor the launcher passes
// (--status-fd N), written whole and unbuffered at each moment a starter acts on (ready, claimed, connected,
// gave_up, progress, restart, run_ended, done). The human lines on stdout/stderr stay as they are; this is
// what programs read. The events and their fields: docs/status-channel.md (kStatusVersion is its "v").
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace swarmform::server {

inline constexpr int kStatusVersion = 1;

class StatusChannel {
 public:
  StatusChannel() = default;  // no channel: emit does nothing
  explicit StatusChannel(int fd);
  ~StatusChannel();
  StatusChannel(const StatusChannel&) = delete;
  StatusChannel& operator=(const StatusChannel&) = delete;

  // Writes {"v":kStatusVersion,"event":event, ...fields} and a newline. A channel that cannot be written (its
  // reader is gone) is said once on stderr and then left alone: the run does not depend on its starter.
  void emit(const std::string& event, nlohmann::ordered_json fields = nlohmann::ordered_json::object());
  // The same with "line": `human`, then `human` on stdout (flushed): a moment whose human line a reader of
  // the world's output may leave out, as it shows the moment itself. The status line goes first, so that a
  // reader of both has it before the stdout line.
  void emit_and_print(const std::string& event, nlohmann::ordered_json fields, const std::string& human);

 private:
  int fd_ = -1;
};

}  // namespace swarmform::server
