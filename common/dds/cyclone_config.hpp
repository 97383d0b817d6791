// The project's own Cyclone DDS configuration, generated in code and applied with dds_create_domain, so a run
// never depends on CYCLONEDDS_URI or on what the default configuration picks on this host.
//
// Star discovery (docs/design-notes/dds-discovery.md): loopback has no multicast, and a full
// mesh of 128 processes takes minutes to converge. So the world takes ParticipantIndex 0 (a fixed discovery
// port), every agent takes ParticipantIndex none (an ephemeral port, no limit of 9 a host) and has the world
// as its only peer: agents never discover each other, and the world discovers each agent once. Death
// detection is the agents' command writers' liveliness (MANUAL_BY_TOPIC, 500 ms, qos.hpp): a SIGKILLed
// agent's writer loses liveliness at the world within ~0.5 s. Participant leases (5 s) tell no death.
//
// A user's configuration (--dds-config FILE, else CYCLONEDDS_URI) is merged on top: cyclone_config_string
// gives Cyclone our document first and the user's second, and Cyclone lets a later document's settings
// override an earlier one's (docs/dds-config.md says what may be overridden).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/dds/security_config.hpp"

namespace swarmform::dds {

enum class Role {
  World,  // ParticipantIndex 0: the fixed discovery port the agents peer with
  Agent,  // ParticipantIndex none, the world as the only peer (agents, bench robots, test programs)
};

// A user's Cyclone DDS configuration document, read and checked by user_dds_config.
struct UserDdsConfig {
  std::string source;  // where it came from, for messages: "--dds-config /abs/path" or "CYCLONEDDS_URI=..."
  std::string xml;     // the document, given to Cyclone as an XML fragment after ours
};

struct DdsSettings {
  std::uint32_t domain = 0;  // DDS domain id, 0..kMaxDomain
  Role role = Role::Agent;
  // Agents: the world's address, their only discovery peer. Loopback by default; another host's address for
  // agents on other hosts (no code change, just this).
  std::string world_host = "127.0.0.1";
  // The local interface to use (its address). Empty: loopback when world_host is loopback, else Cyclone's own
  // choice of interface.
  std::string interface_address;
  // Agent role: more discovery peers ("host:port") beside the world. For test programs that play a forger
  // on the host, which peers with an agent directly (tests/integration/rogue_agent.cpp forge).
  std::vector<std::string> extra_peers;
  // A user's Cyclone XML merged on top of ours (user_dds_config), or none.
  std::optional<UserDdsConfig> user;
  // DDS Security (`--security-dir`, docs/security.md): when set, the domain's <Security> section
  // (security_config.hpp); the participant then talks only to participants of the same run's authority.
  std::optional<SecurityFiles> security;
  // The world's face (docs/wire.md "Faces"): World role, the face this participant is (ParticipantIndex
  // `face`, its own Cyclone domain instance in the world's process); Agent role, the face the agent peers
  // with (face_of its robot id). 0 for everything else.
  std::uint32_t face = 0;
};

inline constexpr std::uint32_t kMaxDomain = 232;
inline constexpr std::uint32_t kMaxRexmitMessageBytes = 14720;  // Cyclone's MaxMessageSize default
inline constexpr std::uint32_t kPortBase = 7400;
inline constexpr std::uint32_t kDomainGain = 100;  // ports per domain: all fixed ports stay below 32768

// The world's SPDP unicast port for a domain (RTPS port mapping: base + gain*domain + 10 + 2*index, index 0).
std::uint16_t world_discovery_port(std::uint32_t domain);

// Faces (docs/wire.md "Faces"): the world speaks to its robots through one participant per block of
// kRobotsPerFace ids, each in a Cyclone domain instance of its own (so agents of one block never discover the
// per-robot endpoints of another: discovery grows as N x 64, not N^2). Face f is ParticipantIndex f, so at
// most kMaxFaces fit in a domain's 100 ports (10 + 2f + 1 < 100); ids past the last face share it.
inline constexpr std::uint32_t kRobotsPerFace = 64;
inline constexpr std::uint32_t kMaxFaces = 45;
std::uint32_t face_of(std::uint32_t robot_id);
// Faces a world of `robots` robots has (face_of(robots - 1) + 1; 1 for none).
std::uint32_t face_count(std::size_t robots);
// Face f's SPDP unicast port (world_discovery_port + 2f): where an agent of that face sends its discovery.
std::uint16_t face_discovery_port(std::uint32_t domain, std::uint32_t face);
// The domain id a participant is created with in its own process (dds_create_domain): the domain for face 0;
// for face f another id, distinct per face (a process holds one instance per id), whose ports and wire domain
// id are the domain's (Discovery/ExternalDomainId). Stays within 0..230, the range DDS Security accepts.
std::uint32_t local_domain_id(const DdsSettings& settings);

// The receive buffer a world face asks for (Internal/SocketReceiveBufferSize min), given the host's
// net.core.rmem_max: kWorldReceiveBufferBytes when the host allows it, else rmem_max (Cyclone then gets what
// it asked for and says nothing; asking past rmem_max makes it log an error at every start); 0 (Cyclone's own
// 1 MiB) when rmem_max is below that.
inline constexpr std::uint32_t kWorldReceiveBufferBytes = 4u << 20;
std::uint32_t world_receive_buffer(std::uint64_t rmem_max);

// Our own XML configuration for these settings (throws std::invalid_argument on a bad domain or address).
std::string cyclone_config_xml(const DdsSettings& settings);

// What dds_create_domain is given: our document, then the user's (if any), comma-separated as Cyclone's
// configuration lists are.
std::string cyclone_config_string(const DdsSettings& settings);

// The configuration in force, for --print-dds-config: our document indented, then the user's as written,
// each under a comment naming its source and the merge order.
std::string cyclone_config_listing(const DdsSettings& settings, const std::string& program);

// The user's configuration: the file `flag_file` (--dds-config) when not empty, else CYCLONEDDS_URI when
// `env_uri` is set and not empty (a file path, a file:// URI or an inline <CycloneDDS> document), else none.
// Throws std::invalid_argument naming the source on a missing, unreadable, empty or non-XML file, or a list.
std::optional<UserDdsConfig> user_dds_config(const std::string& flag_file, const char* env_uri);

}  // namespace swarmform::dds
