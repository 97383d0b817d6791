// Which frames go to which page, live and in replay (viewer/README.md "Rates"): a page that says it drew a
// frame (`{"cmd": "drawn"}`) has at most kInFlight frames sent to it and not yet drawn, one being drawn and
// one on its way. A frame that comes while it is full waits for it, replaced by any newer one, and goes when
// it says it drew one. So a page slower than the frames shows the newest frame a frame late, never the
// seconds of frames the socket buffers would hold (5.2 s at 256 robots, live; a replay's seek shown after
// the backlog). A client that never says "drawn" (a script on the page's protocol) gets every frame.
//
// A replay's frame says whether the timeline playing on made it (`played`) or a jump did (a seek, a play
// from the start): the page counts ticks/s over played frames only. A page that skipped a jump's frame gets
// the next one as a jump too, or it would count the jump as ticks played.
#pragma once

#include <algorithm>
#include <cstdint>
#include <map>
#include <vector>

#include "viewer/web_server.hpp"

namespace swarmform::viewer {

class PageFlow {
 public:
  static constexpr int kInFlight = 2;

  struct Send {
    ClientId client;
    bool jump;  // send it as a jump (replay: `played` false)
  };

  // A page opened; `with_frame`: it was sent the frame of now at once.
  void opened(ClientId c, bool with_frame) { pages_[c].in_flight = with_frame ? 1 : 0; }
  void closed(ClientId c) { pages_.erase(c); }

  // A new frame (`jump`: not the timeline playing on): the pages to send it to now; the others get the
  // newest frame when they say they drew one.
  std::vector<Send> offer(bool jump) {
    std::vector<Send> now;
    for (auto& [client, page] : pages_) {
      if (page.acks && page.in_flight >= kInFlight) {
        if (page.waiting) ++skipped_;
        page.waiting = true;
        page.jumped = page.jumped || jump;
        continue;
      }
      ++page.in_flight;
      now.push_back({client, jump});
    }
    return now;
  }

  // Page `c` drew a frame: true (and `jump` set) when the newest frame, which waited for it, is to go now.
  bool drawn(ClientId c, bool& jump) {
    const auto it = pages_.find(c);
    if (it == pages_.end()) return false;
    Page& page = it->second;
    page.acks = true;
    page.in_flight = std::max(0, page.in_flight - 1);
    if (!page.waiting) return false;
    jump = page.jumped;
    page.waiting = false;
    page.jumped = false;
    ++page.in_flight;
    return true;
  }

  // Frames a page never got: a newer one replaced them while it drew.
  std::uint64_t skipped() const { return skipped_; }
  int in_flight(ClientId c) const {
    const auto it = pages_.find(c);
    return it == pages_.end() ? 0 : it->second.in_flight;
  }

 private:
  struct Page {
    int in_flight = 0;
    bool waiting = false;  // a frame came while it was full: the newest goes when it says drawn
    bool jumped = false;   // one of the frames that waited was a jump
    bool acks = false;     // it said "drawn" once: paced from then on
  };
  std::map<ClientId, Page> pages_;
  std::uint64_t skipped_ = 0;
};

}  // namespace swarmform::viewer
