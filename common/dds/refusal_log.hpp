// Refused wire samples, counted and said at most once a second per writer (docs/wire.md "Refusals"): a
// writer that sends a thousand bad samples a second costs one stderr line a second with the count, never one
// per sample. The number of writers remembered is bounded (the oldest are forgotten; their counts stay in
// the total).
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <unordered_map>

namespace swarmform::dds {

class RefusalLog {
 public:
  // `who`: the prefix of every line ("robot_agent 3", "world_server"); lines go to `out`.
  RefusalLog(std::string who, std::ostream& out);

  // One refused sample of `what` ("packet", "command", ...) from `writer` (a publication handle), for
  // `reason`. `now_ns`: a monotonic time. Says "<who>: refused N <what> sample(s) from <writer_text>:
  // <reason>" when this writer was last said a second or more ago (or never), counting the samples since.
  void refuse(std::uint64_t writer, const std::string& writer_text, const char* what,
              const std::string& reason, std::int64_t now_ns);
  std::uint64_t total() const { return total_; }

 private:
  struct Writer {
    std::int64_t said_at = 0;
    std::uint64_t unsaid = 0;
    bool said = false;
  };
  static constexpr std::size_t kMaxWriters = 4096;
  std::string who_;
  std::ostream& out_;
  std::unordered_map<std::uint64_t, Writer> writers_;
  std::uint64_t total_ = 0;
};

}  // namespace swarmform::dds
