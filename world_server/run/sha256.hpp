// An incremental SHA-256 (OpenSSL's EVP interface) for the trajectory hash: the recorded poses are fed in as
// they are recorded, and the digest can be read at any time without ending the stream.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace swarmform::world {

class Sha256 {
 public:
  Sha256();
  ~Sha256();
  Sha256(const Sha256&) = delete;
  Sha256& operator=(const Sha256&) = delete;

  void update(const void* data, std::size_t size);
  // The bit pattern of a double, as 8 bytes little-endian (the same on every machine we run on).
  void update_double(double value);
  // Lower-case hex of the digest of everything fed so far; the stream can go on afterwards.
  std::string hex_digest() const;

 private:
  void* ctx_;  // EVP_MD_CTX*, kept opaque so that users do not include OpenSSL
};

// One-shot convenience.
std::string sha256_hex(const std::string& data);

}  // namespace swarmform::world
