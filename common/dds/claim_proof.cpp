#include "common/dds/claim_proof.hpp"

#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/hmac.h>

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <vector>

#include "common/hex.hpp"

namespace swarmform::dds {
namespace {

void put_le(std::vector<std::uint8_t>& out, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

std::vector<std::uint8_t> labelled(std::string_view label) {
  std::vector<std::uint8_t> out(label.begin(), label.end());
  out.push_back(0);
  return out;
}

std::array<std::uint8_t, 32> hmac(std::span<const std::uint8_t> key, const std::vector<std::uint8_t>& data) {
  std::array<std::uint8_t, 32> out{};
  unsigned int len = 0;
  if (HMAC(EVP_sha256(), key.data(), static_cast<int>(key.size()), data.data(), data.size(), out.data(),
           &len) == nullptr ||
      len != out.size()) {
    throw std::runtime_error("HMAC-SHA-256 failed (libcrypto)");
  }
  return out;
}

}  // namespace

ClaimToken claim_token(const RunSecret& secret, std::uint64_t run_nonce, RobotId id) {
  std::vector<std::uint8_t> data = labelled("swarmform claim token");
  put_le(data, run_nonce, 8);
  put_le(data, id, 4);
  return hmac(secret, data);
}

ClaimProof claim_proof(const ClaimToken& token, std::uint64_t run_nonce, RobotId id,
                       std::uint64_t claim_nonce, const WriterGuid& writer) {
  std::vector<std::uint8_t> data = labelled("swarmform claim");
  put_le(data, run_nonce, 8);
  put_le(data, id, 4);
  put_le(data, claim_nonce, 8);
  data.insert(data.end(), writer.begin(), writer.end());
  return hmac(token, data);
}

bool proof_valid(const RunSecret& secret, std::uint64_t run_nonce, RobotId id, std::uint64_t claim_nonce,
                 const WriterGuid& writer, std::span<const std::uint8_t> proof) {
  if (proof.size() != ClaimProof{}.size()) return false;
  const ClaimProof want = claim_proof(claim_token(secret, run_nonce, id), run_nonce, id, claim_nonce, writer);
  return CRYPTO_memcmp(want.data(), proof.data(), want.size()) == 0;
}

std::optional<std::array<std::uint8_t, 32>> parse_key_hex(std::string_view hex) {
  const auto bytes = from_hex(hex);
  std::array<std::uint8_t, 32> out{};
  if (!bytes || bytes->size() != out.size()) return std::nullopt;
  std::copy(bytes->begin(), bytes->end(), out.begin());
  return out;
}

std::optional<std::array<std::uint8_t, 32>> take_key_from_env(const char* name) {
  const char* value = std::getenv(name);
  if (value == nullptr) return std::nullopt;
  const auto key = parse_key_hex(value);
  ::unsetenv(name);
  if (!key) throw std::invalid_argument(std::string(name) + ": want 64 hex digits (32 bytes)");
  return key;
}

}  // namespace swarmform::dds
