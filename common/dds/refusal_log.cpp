#include "common/dds/refusal_log.hpp"

namespace swarmform::dds {

RefusalLog::RefusalLog(std::string who, std::ostream& out) : who_(std::move(who)), out_(out) {}

void RefusalLog::refuse(std::uint64_t writer, const std::string& writer_text, const char* what,
                        const std::string& reason, std::int64_t now_ns) {
  ++total_;
  if (writers_.size() >= kMaxWriters && writers_.find(writer) == writers_.end()) writers_.clear();
  Writer& w = writers_[writer];
  ++w.unsaid;
  if (w.said && now_ns - w.said_at < 1000000000) return;
  out_ << who_ << ": refused " << w.unsaid << " " << what << " sample(s) from " << writer_text << ": "
       << reason << std::endl;
  w.said = true;
  w.said_at = now_ns;
  w.unsaid = 0;
}

}  // namespace swarmform::dds
