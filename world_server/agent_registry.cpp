#include "world_server/agent_registry.hpp"

namespace swarmform::server {

AgentRegistry::AgentRegistry(std::size_t robots, ClaimPolicy policy) : policy_(policy), owners_(robots) {}

std::string AgentRegistry::unissued_refusal(RobotId id, const Owner& o,
                                            const ClaimCredentials& credentials) const {
  if (policy_ == ClaimPolicy::Open || credentials.issued) return {};
  if (o.ever && credentials.guid != dds::WriterGuid{} && credentials.guid == o.guid) return {};  // its owner
  const bool first_open = policy_ == ClaimPolicy::FirstClaimsOpen;
  if (first_open && !o.ever && !running_)
    return {};  // a start by hand: every id claimed once, before the run
  const std::string k = std::to_string(id);
  const std::string why = !first_open ? "this run's ids go only to agents its starter issued"
                          : o.ever    ? "id " + k + " had an owner"
                                      : "the run is under way";
  return why + ": a claim needs a valid proof from robot " + k +
         "'s token, and this one has none; an agent started by hand may take an owned id only in a world "
         "started with --open-rejoin";
}

ClaimResult AgentRegistry::claim(RobotId id, dds::PublicationHandle writer, std::uint32_t pid,
                                 std::uint64_t claim_nonce, const ClaimCredentials& credentials) {
  if (id >= owners_.size()) {
    return {ClaimOutcome::OutOfRange, "no robot " + std::to_string(id) + " in this run (ids 0.." +
                                          std::to_string(owners_.size() - 1) + ")"};
  }
  Owner& o = owners_[id];
  if (o.alive && o.writer == writer) {
    o.lapsed = false;  // its sample is proof of life
    return {ClaimOutcome::Repeated, ""};
  }
  const bool rebinds = o.alive && claim_nonce != 0 && o.claim_nonce == claim_nonce && o.pid == pid;
  if (o.alive && !o.lapsed && !rebinds) {
    return {ClaimOutcome::Refused, "id " + std::to_string(id) + " is already owned by a live agent (pid " +
                                       std::to_string(o.pid) + ")"};
  }
  if (std::string why = unissued_refusal(id, o, credentials); !why.empty()) {
    return {ClaimOutcome::Unproven, std::move(why)};
  }
  if (rebinds) {
    // At 1024 agents on 2 cores the world refused such claims and the agents exited: the run never started.
    by_writer_.erase(o.writer);  // the old handle's loss, when DDS reports it, is nobody's
    lost_writer_.erase(o.writer);
    o.writer = writer;
    if (credentials.guid != dds::WriterGuid{}) o.guid = credentials.guid;
    o.lapsed = false;
    by_writer_[writer] = id;
    return {ClaimOutcome::Rebound, ""};
  }
  const bool taken_over = o.ever;
  if (o.writer != 0) {
    by_writer_.erase(o.writer);
    lost_writer_.erase(o.writer);
  }
  o = Owner{.writer = writer,
            .pid = pid,
            .claim_nonce = claim_nonce,
            .guid = credentials.guid,
            .alive = true,
            .lapsed = false,
            .ever = true};
  by_writer_[writer] = id;
  return {taken_over ? ClaimOutcome::TakenOver : ClaimOutcome::Accepted, ""};
}

bool AgentRegistry::owns(RobotId id, dds::PublicationHandle writer) const {
  return id < owners_.size() && owners_[id].alive && owners_[id].writer == writer;
}

std::optional<RobotId> AgentRegistry::owner_of(dds::PublicationHandle writer) const {
  const auto it = by_writer_.find(writer);
  if (it == by_writer_.end()) return std::nullopt;
  return it->second;
}

std::optional<RobotId> AgentRegistry::lose(dds::PublicationHandle writer) {
  const auto it = by_writer_.find(writer);
  if (it == by_writer_.end()) return std::nullopt;
  const RobotId id = it->second;
  by_writer_.erase(it);
  lost_writer_[writer] = id;
  owners_[id].alive = false;
  owners_[id].lapsed = false;
  return id;
}

std::optional<RobotId> AgentRegistry::lapse(dds::PublicationHandle writer) {
  const auto it = by_writer_.find(writer);
  if (it == by_writer_.end()) return std::nullopt;
  owners_[it->second].lapsed = true;
  return it->second;
}

std::optional<RobotId> AgentRegistry::regain(dds::PublicationHandle writer) {
  if (const auto live = by_writer_.find(writer); live != by_writer_.end()) {
    owners_[live->second].lapsed = false;
    return std::nullopt;
  }
  const auto it = lost_writer_.find(writer);
  if (it == lost_writer_.end()) return std::nullopt;
  const RobotId id = it->second;
  lost_writer_.erase(it);
  owners_[id].alive = true;
  by_writer_[writer] = id;
  return id;
}

std::size_t AgentRegistry::connected_count() const {
  std::size_t n = 0;
  for (const Owner& o : owners_) n += o.alive ? 1 : 0;
  return n;
}

std::vector<RobotId> AgentRegistry::missing() const {
  std::vector<RobotId> out;
  for (std::size_t i = 0; i < owners_.size(); ++i) {
    if (!owners_[i].alive) out.push_back(static_cast<RobotId>(i));
  }
  return out;
}

std::string_view to_string(ClaimOutcome outcome) {
  switch (outcome) {
    case ClaimOutcome::Accepted:
      return "accepted";
    case ClaimOutcome::Repeated:
      return "repeated";
    case ClaimOutcome::Rebound:
      return "rebound";
    case ClaimOutcome::TakenOver:
      return "taken_over";
    case ClaimOutcome::Refused:
      return "refused";
    case ClaimOutcome::OutOfRange:
      return "out_of_range";
    case ClaimOutcome::Unproven:
      return "unproven";
  }
  return "unknown";
}

}  // namespace swarmform::server
