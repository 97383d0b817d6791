#include "common/dds/cyclone_config.hpp"

#include <stdexcept>

namespace swarmform::dds {

namespace {

bool is_loopback(const std::string& host) {
  return host == "localhost" || host.rfind("127.", 0) == 0 || host == "::1";
}

// Host names and IPv4/IPv6 literals only: the value goes into an XML attribute.
void check_address(const std::string& what, const std::string& value) {
  if (value.empty()) throw std::invalid_argument(what + " is empty");
  for (char c : value) {
    const bool ok = (c >= '0' && c <= '9') || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '.' ||
                    c == '-' || c == ':' || c == '_';
    if (!ok) throw std::invalid_argument(what + " '" + value + "' is not a host name or address");
  }
}

}  // namespace

std::uint16_t world_discovery_port(std::uint32_t domain) {
  return static_cast<std::uint16_t>(kPortBase + kDomainGain * domain + 10);
}

std::string cyclone_config_xml(const DdsSettings& s) {
  if (s.domain > kMaxDomain) {
    throw std::invalid_argument("DDS domain " + std::to_string(s.domain) + " is out of range 0.." +
                                std::to_string(kMaxDomain));
  }
  std::string iface = s.interface_address;
  if (iface.empty() && (s.role == Role::World || is_loopback(s.world_host))) iface = "127.0.0.1";
  if (!iface.empty()) check_address("interface address", iface);

  std::string xml = "<CycloneDDS><Domain id=\"any\"><General>";
  if (!iface.empty()) xml += "<Interfaces><NetworkInterface address=\"" + iface + "\"/></Interfaces>";
  // Loopback has no multicast flag; say so rather than let Cyclone find out, on every interface alike.
  xml += "<AllowMulticast>false</AllowMulticast>";
  // Retransmissions packed up to the normal message size (14720 B) rather than Cyclone's 1456 B. An agent
  // learns the world's ~260 endpoints (a packet writer per robot) from retransmissions of the world's SEDP
  // history, ~450 B each: 3 to a datagram made 256 agents receive ~190,000 SEDP submessages in ~60,000
  // datagrams while they connected (tcpdump, BENCHMARKS.md), and their receive threads the largest share of
  // their CPU. Measured: connected 17.0-21.2 s -> 9.9-11.9 s.
  xml += "<MaxRexmitMessageSize>" + std::to_string(kMaxRexmitMessageBytes) + "B</MaxRexmitMessageSize>";
  xml += "</General><Discovery>";
  // A domain gain of 100 (RTPS default 250) keeps every domain's fixed ports below Linux's ephemeral range
  // (32768-60999): with 250, a domain above ~100 puts the world's port among the ephemeral ones that any
  // agent socket may hold, and the world then fails to start ("failed to create unicast sockets"), as seen.
  xml += "<Ports><Base>" + std::to_string(kPortBase) + "</Base><DomainGain>" + std::to_string(kDomainGain) +
         "</DomainGain></Ports>";
  if (s.role == Role::World) {
    xml += "<ParticipantIndex>0</ParticipantIndex>";
  } else {
    check_address("world host", s.world_host);
    xml += "<ParticipantIndex>none</ParticipantIndex><Peers><Peer address=\"" + s.world_host + ":" +
           std::to_string(world_discovery_port(s.domain)) + "\"/>";
    for (const std::string& peer : s.extra_peers) {
      check_address("peer", peer);
      xml += "<Peer address=\"" + peer + "\"/>";
    }
    xml += "</Peers>";
    // Re-announce every second so an agent started before the world is matched soon after it comes up.
    xml += "<SPDPInterval>1s</SPDPInterval>";
  }
  // Participant leases: 5 s on every process. Death is told by the writers' liveliness (qos.hpp: an agent's
  // command writer, 500 ms; the world's writers, 2 s), not by the participant lease. A participant without
  // AUTOMATIC writers still sends a reliable liveliness message (with heartbeat and acknowledgement) to every
  // peer each 0.8 x its lease: an agent's 1 s lease cost the world ~840 submessages a second from 256 agents
  // (tcpdump, BENCHMARKS.md).
  xml += "<LeaseDuration>5s</LeaseDuration></Discovery>";
  // iceoryx shared memory is compiled in but loses samples with keep-last 1 and ignores partitions in 0.10.2.
  xml += "<SharedMemory><Enable>false</Enable></SharedMemory>";
  if (s.security) xml += security_config_xml(*s.security);
  xml += "</Domain></CycloneDDS>";
  return xml;
}

}  // namespace swarmform::dds
