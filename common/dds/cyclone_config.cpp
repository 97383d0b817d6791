#include "common/dds/cyclone_config.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
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

constexpr std::size_t kMaxUserConfigBytes = 1 << 20;

}  // namespace

std::uint16_t world_discovery_port(std::uint32_t domain) {
  return static_cast<std::uint16_t>(kPortBase + kDomainGain * domain + 10);
}

std::uint32_t face_of(std::uint32_t robot_id) {
  return std::min(robot_id / kRobotsPerFace, kMaxFaces - 1);
}

std::uint32_t face_count(std::size_t robots) {
  return robots == 0
             ? 1
             : face_of(static_cast<std::uint32_t>(std::min<std::size_t>(robots - 1, 0xffffffffu))) + 1;
}

std::uint32_t world_receive_buffer(std::uint64_t rmem_max) {
  constexpr std::uint64_t kCycloneDefault = 1u << 20;
  if (rmem_max <= kCycloneDefault) return 0;
  return static_cast<std::uint32_t>(std::min<std::uint64_t>(rmem_max, kWorldReceiveBufferBytes));
}

std::uint16_t face_discovery_port(std::uint32_t domain, std::uint32_t face) {
  return static_cast<std::uint16_t>(world_discovery_port(domain) + 2 * face);
}

std::uint32_t local_domain_id(const DdsSettings& s) {
  constexpr std::uint32_t kSecureDomains = 231;  // 0..230: Cyclone 0.10.2's access-control parser
  if (s.role != Role::World || s.face == 0) return s.domain;
  return (s.domain + s.face) % kSecureDomains;
}

// The document is built from one function per section of <Domain>, so a section can be added (a Security
// section for --secure) without touching the others.
namespace {

std::string general_section(const DdsSettings& s) {
  std::string iface = s.interface_address;
  if (iface.empty() && (s.role == Role::World || is_loopback(s.world_host))) iface = "127.0.0.1";
  if (!iface.empty()) check_address("interface address", iface);

  std::string xml = "<General>";
  if (!iface.empty()) xml += "<Interfaces><NetworkInterface address=\"" + iface + "\"/></Interfaces>";
  // Loopback has no multicast flag; say so rather than let Cyclone find out, on every interface alike.
  xml += "<AllowMulticast>false</AllowMulticast>";
  // Retransmissions packed up to the normal message size (14720 B) rather than Cyclone's 1456 B. An agent
  // learns the world's ~260 endpoints (a packet writer per robot) from retransmissions of the world's SEDP
  // history, ~450 B each: 3 to a datagram made 256 agents receive ~190,000 SEDP submessages in ~60,000
  // datagrams while they connected (tcpdump, BENCHMARKS.md), and their receive threads the largest share of
  // their CPU. Measured: connected 17.0-21.2 s -> 9.9-11.9 s.
  xml += "<MaxRexmitMessageSize>" + std::to_string(kMaxRexmitMessageBytes) + "B</MaxRexmitMessageSize>";
  return xml + "</General>";
}

std::string discovery_section(const DdsSettings& s) {
  std::string xml = "<Discovery>";
  // A domain gain of 100 (RTPS default 250) keeps every domain's fixed ports below Linux's ephemeral range
  // (32768-60999): with 250, a domain above ~100 puts the world's port among the ephemeral ones that any
  // agent socket may hold, and the world then fails to start ("failed to create unicast sockets"), as seen.
  xml += "<Ports><Base>" + std::to_string(kPortBase) + "</Base><DomainGain>" + std::to_string(kDomainGain) +
         "</DomainGain></Ports>";
  if (s.face >= kMaxFaces) {
    throw std::invalid_argument("face " + std::to_string(s.face) + " is out of range 0.." +
                                std::to_string(kMaxFaces - 1));
  }
  if (s.role == Role::World) {
    // Face f: ParticipantIndex f, in a domain instance of its own whose wire domain id (and so its ports) is
    // the run's (local_domain_id).
    xml += "<ParticipantIndex>" + std::to_string(s.face) + "</ParticipantIndex><ExternalDomainId>" +
           std::to_string(s.domain) + "</ExternalDomainId>";
  } else {
    check_address("world host", s.world_host);
    xml += "<ParticipantIndex>none</ParticipantIndex><Peers><Peer address=\"" + s.world_host + ":" +
           std::to_string(face_discovery_port(s.domain, s.face)) + "\"/>";
    for (const std::string& peer : s.extra_peers) {
      check_address("peer", peer);
      xml += "<Peer address=\"" + peer + "\"/>";
    }
    xml += "</Peers>";
    // Re-announced every 2 s: an agent started before the world is matched within 2 s of its coming up
    // (`swarm run` starts the world first, so its agents' first announcement finds it). Every second, as it
    // was, the world parsed 1024 announcements a second and each agent sent one: a third of an idle agent's
    // CPU and two thirds of the world's while 1024 wait for the run (bench/scale/README.md). 5 s was
    // cheaper still, but an outsider started before a short secure run never saw its world
    // (scripts.secure_e2e).
    xml += "<SPDPInterval>2s</SPDPInterval>";
  }
  // Participant leases: 30 s on every process. Death is told by the writers' liveliness (qos.hpp: an agent's
  // command writer, 500 ms; the world's writers, 2 s), not by the participant lease. A participant without
  // AUTOMATIC writers still sends a reliable liveliness message (with heartbeat and acknowledgement) to every
  // peer each 0.8 x its lease: an agent's 1 s lease cost the world ~840 submessages a second from 256 agents
  // (tcpdump, BENCHMARKS.md). Long, because a participant whose lease ran out while its process was starved
  // (1024 agents starting on 2 cores; 5 s was too short) is forgotten, and Cyclone 0.10.2 then ignores its
  // announcements for a while ("recently deleted"): agents stayed undiscovered for minutes. What it costs: a
  // crashed process's endpoints stay matched 30 s (its death is still seen by its writer's lease).
  return xml + "<LeaseDuration>30s</LeaseDuration></Discovery>";
}

std::uint64_t host_rmem_max() {
  std::ifstream in("/proc/sys/net/core/rmem_max");
  std::uint64_t v = 0;
  return (in >> v) ? v : 0;
}

// The world's sockets sized for the run. While 1024 agents start, each face's discovery socket takes the
// SPDP, SEDP, heartbeats and acknowledgements of its 64 agents (~2,000 datagrams a second in all); Cyclone's
// 1 MiB (2 MiB once the kernel doubles it) filled whenever the world's receive threads were kept off the CPU
// for about a second on the loaded 2-core host: 54-78 thousand datagrams dropped a start
// (bench/scale/README.md). Linux doubles what is asked, so 4 MiB asked is 8 MiB of queue. Agents receive
// little: Cyclone's default.
std::string internal_section(const DdsSettings& s) {
  if (s.role != Role::World) return "";
  const std::uint32_t bytes = world_receive_buffer(host_rmem_max());
  if (bytes == 0) return "";
  return "<Internal><SocketReceiveBufferSize min=\"" + std::to_string(bytes) + "B\"/></Internal>";
}

// iceoryx shared memory is compiled in but loses samples with keep-last 1 and ignores partitions in 0.10.2.
std::string shared_memory_section() {
  return "<SharedMemory><Enable>false</Enable></SharedMemory>";
}

// Our document indented two spaces a level; an element holding only text stays on one line. Only for our own
// generated XML (no comments, no '<' in text).
std::string indented(const std::string& xml) {
  std::string out;
  int depth = 0;
  std::size_t i = 0;
  while (i < xml.size()) {
    const std::size_t close = xml.find('>', i);
    if (xml[i] != '<' || close == std::string::npos) break;
    const std::string tag = xml.substr(i, close - i + 1);
    i = close + 1;
    if (tag[1] == '/') {
      --depth;
      out += std::string(2 * static_cast<std::size_t>(depth), ' ') + tag + "\n";
      continue;
    }
    out += std::string(2 * static_cast<std::size_t>(depth), ' ') + tag;
    if (tag[tag.size() - 2] == '/') {
      out += "\n";
      continue;
    }
    const std::size_t next = xml.find('<', i);
    if (next != std::string::npos && next > i && xml.compare(next, 2, "</") == 0) {  // text, then its end tag
      const std::size_t end = xml.find('>', next);
      out += xml.substr(i, end + 1 - i) + "\n";
      i = end + 1;
      continue;
    }
    out += "\n";
    ++depth;
  }
  return out;
}

std::string trimmed(const std::string& text) {
  const std::size_t b = text.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const std::size_t e = text.find_last_not_of(" \t\r\n");
  return text.substr(b, e + 1 - b);
}

UserDdsConfig read_user_file(const std::string& path, const std::string& source) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path abs = fs::absolute(path, ec);
  const std::string where = source + " " + (ec ? path : abs.string());
  if (!fs::exists(abs, ec)) throw std::invalid_argument(where + ": no such file");
  if (fs::is_directory(abs, ec)) throw std::invalid_argument(where + ": is a directory, not an XML file");
  std::ifstream in(abs, std::ios::binary);
  if (!in) throw std::invalid_argument(where + ": cannot be read");
  std::ostringstream text;
  text << in.rdbuf();
  if (text.str().size() > kMaxUserConfigBytes) {
    throw std::invalid_argument(where + ": larger than " + std::to_string(kMaxUserConfigBytes) +
                                " bytes; not a Cyclone DDS configuration");
  }
  std::string xml = trimmed(text.str());
  if (xml.rfind("\xEF\xBB\xBF", 0) == 0) xml = trimmed(xml.substr(3));  // a UTF-8 byte order mark
  if (xml.empty()) throw std::invalid_argument(where + ": is empty; want a <CycloneDDS> XML document");
  if (xml.front() != '<' || xml.find("<CycloneDDS") == std::string::npos) {
    throw std::invalid_argument(where +
                                ": is not a Cyclone DDS configuration (want an XML document whose "
                                "root element is <CycloneDDS>)");
  }
  return UserDdsConfig{where, xml};
}

}  // namespace

std::string cyclone_config_xml(const DdsSettings& s) {
  if (s.domain > kMaxDomain) {
    throw std::invalid_argument("DDS domain " + std::to_string(s.domain) + " is out of range 0.." +
                                std::to_string(kMaxDomain));
  }
  return "<CycloneDDS><Domain id=\"any\">" + general_section(s) + discovery_section(s) + internal_section(s) +
         shared_memory_section() + (s.security ? security_config_xml(*s.security) : std::string()) +
         "</Domain></CycloneDDS>";
}

std::string cyclone_config_string(const DdsSettings& s) {
  std::string config = cyclone_config_xml(s);
  if (s.user) config += "," + s.user->xml;
  return config;
}

std::string cyclone_config_listing(const DdsSettings& s, const std::string& program) {
  const std::string count = s.user ? "2" : "1";
  std::string out = "<!-- The Cyclone DDS configuration of " + program + " on DDS domain " +
                    std::to_string(s.domain) + ": the document";
  out += s.user ? "s below, merged in this order (a setting of the later one overrides the earlier one's; "
                  "docs/dds-config.md) -->\n"
                : " below (no --dds-config, no CYCLONEDDS_URI; docs/dds-config.md) -->\n";
  out += "<!-- 1 of " + count + ": swarmform's own (common/dds/cyclone_config.cpp) -->\n";
  out += indented(cyclone_config_xml(s));
  if (s.user) out += "<!-- 2 of 2: from " + s.user->source + " -->\n" + s.user->xml + "\n";
  return out;
}

std::optional<UserDdsConfig> user_dds_config(const std::string& flag_file, const char* env_uri) {
  if (!flag_file.empty()) return read_user_file(flag_file, "--dds-config");
  if (env_uri == nullptr || trimmed(env_uri).empty()) return std::nullopt;
  const std::string uri = trimmed(env_uri);
  if (uri.front() == '<') {
    if (uri.find("<CycloneDDS") == std::string::npos) {
      throw std::invalid_argument(
          "CYCLONEDDS_URI: an inline document must have the root element <CycloneDDS>");
    }
    return UserDdsConfig{"CYCLONEDDS_URI (inline)", uri};
  }
  if (uri.find(',') != std::string::npos) {
    throw std::invalid_argument("CYCLONEDDS_URI='" + uri +
                                "': a list of configurations is not taken here; give one file (or "
                                "merge them into one and pass --dds-config FILE)");
  }
  const std::string path = uri.rfind("file://", 0) == 0 ? uri.substr(7) : uri;
  return read_user_file(path, "CYCLONEDDS_URI");
}

}  // namespace swarmform::dds
