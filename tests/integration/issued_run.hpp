// A run started as `swarm run` starts one (docs/wire.md "Claim proofs"): the world holds the run's secret and
// nonce, and each agent the test starts as the launcher would gets its id's token. An agent started without
// one is a stranger to such a world: it may take no id.
#pragma once

#include <random>
#include <string>
#include <vector>

#include "common/dds/claim_proof.hpp"

namespace swarmform::testing {

struct IssuedRun {
  dds::RunSecret secret{};
  std::uint64_t run_nonce = 0;

  IssuedRun() {
    std::random_device rd;
    for (auto& b : secret) b = static_cast<std::uint8_t>(rd());
    run_nonce = (static_cast<std::uint64_t>(rd()) << 32 | rd()) | 1;  // never 0
  }
  std::string nonce_hex() const {
    char b[17];
    std::snprintf(b, sizeof b, "%016llx", static_cast<unsigned long long>(run_nonce));
    return b;
  }
  // The world's and the agents' --run-nonce.
  std::vector<std::string> nonce_flags() const { return {"--run-nonce", nonce_hex()}; }
  std::vector<std::string> world_env() const {
    return {std::string(dds::kRunSecretEnv) + "=" + swarmform::to_hex(secret)};
  }
  std::vector<std::string> agent_env(RobotId id) const {
    return {std::string(dds::kClaimTokenEnv) + "=" +
            swarmform::to_hex(dds::claim_token(secret, run_nonce, id))};
  }
};

}  // namespace swarmform::testing
