// Who may take a robot's id (docs/wire.md "Identity and the claim protocol", "Claim proofs"). Whoever starts
// a run draws a secret and hands it to the world out of band (never on the wire); each agent it starts gets
// its id's token, derived from the secret, and every claim it sends carries a proof: an HMAC under its token
// of the run, the id, the claim's own nonce and the GUID of the writer that sends it. The world derives the
// token again and checks the proof. A sniffer learns neither the secret nor a token, and a proof it copies
// is good only for that id, that run and that writer, so replayed from its own writer it proves nothing.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "common/hex.hpp"  // to_hex for the tokens in the environment
#include "common/types.hpp"

namespace swarmform::dds {

using RunSecret = std::array<std::uint8_t, 32>;   // the run's secret (world and launcher only)
using ClaimToken = std::array<std::uint8_t, 32>;  // robot K's token in one run (agent K only)
using ClaimProof = std::array<std::uint8_t, 32>;  // one claim's proof (on the wire, in the claim)
using WriterGuid = std::array<std::uint8_t, 16>;  // a DDS writer's GUID, as Cyclone gives it

// The environment variables that carry the secret to the world and a token to an agent (read once and
// removed from the process's environment, so that no child inherits them).
inline constexpr const char* kRunSecretEnv = "SWARMFORM_RUN_SECRET";
inline constexpr const char* kClaimTokenEnv = "SWARMFORM_CLAIM_TOKEN";

// HMAC-SHA-256(secret, "swarmform claim token" 0 | run_nonce (8 bytes LE) | id (4 bytes LE)).
ClaimToken claim_token(const RunSecret& secret, std::uint64_t run_nonce, RobotId id);
// HMAC-SHA-256(token, "swarmform claim" 0 | run_nonce (8 LE) | id (4 LE) | claim_nonce (8 LE) | writer GUID).
ClaimProof claim_proof(const ClaimToken& token, std::uint64_t run_nonce, RobotId id,
                       std::uint64_t claim_nonce, const WriterGuid& writer);
// Whether `proof` (the claim's bytes, any length) is the proof robot `id`'s token gives this claim. Compared
// in constant time.
bool proof_valid(const RunSecret& secret, std::uint64_t run_nonce, RobotId id, std::uint64_t claim_nonce,
                 const WriterGuid& writer, std::span<const std::uint8_t> proof);

// 64 hex digits into 32 bytes; nullopt for anything else.
std::optional<std::array<std::uint8_t, 32>> parse_key_hex(std::string_view hex);
// Reads and removes the environment variable `name`: nullopt when unset; throws std::invalid_argument
// naming it when it is set but not 64 hex digits.
std::optional<std::array<std::uint8_t, 32>> take_key_from_env(const char* name);

}  // namespace swarmform::dds
