// Who speaks for which robot. The first agent that claims an id owns it: the id is bound to the DDS writer
// (its publication handle) that sent the claim. A second claimant while the owner lives is refused; a
// claimant after the owner died takes the id over (a restarted agent rejoins). The owner itself seen through
// a new writer handle (the same process and claim attempt: DDS forgot its participant, whose lease ran out
// while the machine was starved, and discovered it again) keeps the id on the new handle. Commands are the
// owner's only if they come from the owner's writer. Pure bookkeeping: no DDS, no World (the server acts on
// the answers).
// Who may take an id (docs/wire.md "Claim proofs"): a claim the run's starter issued (its proof checked by
// the server) may take any id these rules allow. One that is not issued may take the id its own writer owns
// or last owned (the same writer GUID: the owner itself, rediscovered or back from a lapse), and, by the
// policy: nothing else when the world holds the run's secret (its starter issues every agent it starts); an
// id nobody has owned, before the run's first round, when it holds none (a world and its agents started by
// hand); a free or dead owner's id too with --open-rejoin.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "common/dds/claim_proof.hpp"
#include "common/dds/identity.hpp"
#include "common/types.hpp"

namespace swarmform::server {

enum class ClaimOutcome {
  Accepted,    // a free id, now bound to this writer
  Repeated,    // this writer already owns it (a re-sent claim): answer again
  Rebound,     // the owner's re-sent claim through a new writer handle: the id moves to it, answer again
  TakenOver,   // the previous owner had died: bound to this writer (a rejoin once the run is going)
  Refused,     // a live writer owns it
  OutOfRange,  // no such robot in this run
  Unproven,    // the id needs a claim the run's starter issued, and this one is not
};

enum class ClaimPolicy {
  IssuedOnly,       // every claim must be issued (the world holds the run's secret)
  FirstClaimsOpen,  // unissued claims may take never-owned ids before the run (no secret: a start by hand)
  Open,             // any claimant may take a free or dead owner's id (--open-rejoin)
};

// What the server knows of a claimant beyond what its sample says of itself.
struct ClaimCredentials {
  dds::WriterGuid guid{};  // its writer's GUID, from discovery (all zero: unknown)
  bool issued = false;     // its proof is valid (or, under --secure, its certificate is the id's)
};

struct ClaimResult {
  ClaimOutcome outcome = ClaimOutcome::Refused;
  std::string reason;  // for the refused agent's message and the log
};

class AgentRegistry {
 public:
  explicit AgentRegistry(std::size_t robots, ClaimPolicy policy = ClaimPolicy::Open);

  // `claim_nonce`: the claimant's nonce for this claim attempt (re-sent claims carry the same); 0: none.
  ClaimResult claim(RobotId id, dds::PublicationHandle writer, std::uint32_t pid,
                    std::uint64_t claim_nonce = 0, const ClaimCredentials& credentials = {});
  // The run's first round is next: from now on an unissued claim takes no id its writer did not own.
  void start_run() { running_ = true; }
  // The live owner of `id` is `writer`.
  bool owns(RobotId id, dds::PublicationHandle writer) const;
  // The robot `writer` owns now, if any.
  std::optional<RobotId> owner_of(dds::PublicationHandle writer) const;
  // `writer` lost liveliness or went away: the robot it owned, if it owned one (then no longer owned).
  std::optional<RobotId> lose(dds::PublicationHandle writer);
  // `writer`'s liveliness lapsed before the run: it keeps its robot and counts as connected, but another
  // claimant may take the id over (an agent restarted after a crash need not wait for the old participant's
  // lease) until its liveliness or a sample of it comes back. The robot, if `writer` owned one.
  std::optional<RobotId> lapse(dds::PublicationHandle writer);
  // `writer`'s liveliness came back (a stalled agent, not a dead one): the robot, if `writer` was its owner
  // when it was lost and nobody has taken the id over since (then owned by it again). A lapsed owner is
  // only no longer lapsed (nullopt: nothing changed).
  std::optional<RobotId> regain(dds::PublicationHandle writer);

  bool connected(RobotId id) const { return id < owners_.size() && owners_[id].alive; }
  // The owner's writer if its liveliness lapsed (lapse) and has not come back.
  std::optional<dds::PublicationHandle> lapsed_writer(RobotId id) const {
    if (id >= owners_.size() || !owners_[id].alive || !owners_[id].lapsed) return std::nullopt;
    return owners_[id].writer;
  }
  std::size_t connected_count() const;
  std::vector<RobotId> missing() const;
  std::uint32_t pid(RobotId id) const { return id < owners_.size() ? owners_[id].pid : 0; }

 private:
  struct Owner {
    dds::PublicationHandle writer = 0;
    std::uint32_t pid = 0;
    std::uint64_t claim_nonce = 0;
    dds::WriterGuid guid{};
    bool alive = false;   // an owner whose writer is alive
    bool lapsed = false;  // alive, but its liveliness lapsed before the run (lapse)
    bool ever = false;    // someone owned it once
  };
  // Why an unissued claim of `o`'s id by `credentials` is refused (empty: it is allowed).
  std::string unissued_refusal(RobotId id, const Owner& o, const ClaimCredentials& credentials) const;

  ClaimPolicy policy_;
  bool running_ = false;
  std::vector<Owner> owners_;
  std::unordered_map<dds::PublicationHandle, RobotId> by_writer_;    // live owners
  std::unordered_map<dds::PublicationHandle, RobotId> lost_writer_;  // owners lost, their id not taken over
};

std::string_view to_string(ClaimOutcome outcome);

}  // namespace swarmform::server
