#include "world_server/run/sha256.hpp"

#include <openssl/evp.h>

#include <array>
#include <bit>
#include <cstring>
#include <stdexcept>

namespace swarmform::world {

namespace {
EVP_MD_CTX* as_ctx(void* p) {
  return static_cast<EVP_MD_CTX*>(p);
}
}  // namespace

Sha256::Sha256() : ctx_(EVP_MD_CTX_new()) {
  if (ctx_ == nullptr || EVP_DigestInit_ex(as_ctx(ctx_), EVP_sha256(), nullptr) != 1) {
    EVP_MD_CTX_free(as_ctx(ctx_));
    throw std::runtime_error("SHA-256: OpenSSL could not initialise a digest");
  }
}

Sha256::~Sha256() {
  EVP_MD_CTX_free(as_ctx(ctx_));
}

void Sha256::update(const void* data, std::size_t size) {
  if (size == 0) return;
  if (EVP_DigestUpdate(as_ctx(ctx_), data, size) != 1) throw std::runtime_error("SHA-256: update failed");
}

void Sha256::update_double(double value) {
  static_assert(std::endian::native == std::endian::little, "the trajectory hash assumes little-endian");
  std::array<unsigned char, sizeof(double)> bytes{};
  std::memcpy(bytes.data(), &value, sizeof(double));
  update(bytes.data(), bytes.size());
}

std::string Sha256::hex_digest() const {
  EVP_MD_CTX* copy = EVP_MD_CTX_new();
  if (copy == nullptr || EVP_MD_CTX_copy_ex(copy, as_ctx(ctx_)) != 1) {
    EVP_MD_CTX_free(copy);
    throw std::runtime_error("SHA-256: could not copy the digest state");
  }
  std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
  unsigned int length = 0;
  const int ok = EVP_DigestFinal_ex(copy, digest.data(), &length);
  EVP_MD_CTX_free(copy);
  if (ok != 1) throw std::runtime_error("SHA-256: final failed");
  static constexpr char kHex[] = "0123456789abcdef";
  std::string hex;
  hex.reserve(2 * length);
  for (unsigned int i = 0; i < length; ++i) {
    hex.push_back(kHex[digest[i] >> 4]);
    hex.push_back(kHex[digest[i] & 0x0f]);
  }
  return hex;
}

std::string sha256_hex(const std::string& data) {
  Sha256 sha;
  sha.update(data.data(), data.size());
  return sha.hex_digest();
}

}  // namespace swarmform::world
