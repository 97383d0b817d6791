#include "world_server/wire_check.hpp"

#include <cstdio>

#include "common/dds/wire_version.hpp"

namespace swarmform::server {

std::string wire_refusal(const dds::CommandSample& s, std::uint64_t run_nonce) {
  if (s.wire_version != dds::kWireVersion) {
    return "wire version " + std::to_string(s.wire_version) + ", this world speaks " +
           std::to_string(dds::kWireVersion);
  }
  if (s.run_nonce != run_nonce) {
    char b[128];
    std::snprintf(b, sizeof b, "run nonce %016llx is not this run's (%016llx): a sample of another run",
                  static_cast<unsigned long long>(s.run_nonce), static_cast<unsigned long long>(run_nonce));
    return b;
  }
  return {};
}

std::string writer_text(const dds::CommandSample& s) {
  char b[64];
  std::snprintf(b, sizeof b, "writer %016llx (pid %u)", static_cast<unsigned long long>(s.writer), s.pid);
  return b;
}

std::string claimant_text(const dds::CommandSample& s, const std::optional<dds::RemoteWriter>& remote) {
  return "pid " + std::to_string(s.pid) +
         (remote ? " (participant " + dds::to_string(remote->participant) + ")" : " (participant unknown)");
}

}  // namespace swarmform::server
