// DDS Security (`--secure`, docs/security.md): the files one participant needs and the <Security> section of
// its Cyclone configuration. Kept apart from cyclone_config.cpp, which appends this section when
// DdsSettings::security is set, so the two change independently.
//
// A security directory (made per run by the launcher, scripts/swarmform/security.py; docs/security.md) holds:
//   ca.pem                          the run's certificate authority (identities and signed documents)
//   governance.p7s                  the domain's rules, signed by the CA
//   <identity>.pem / .key           an identity's certificate and private key (the key 0600)
//   <identity>.permissions.p7s      what that identity may publish and subscribe, signed by the CA
// with the identities `world`, `robot-K` (one per robot id) and `observer`.
//
// The Cyclone security plugins (libdds_security_auth, _ac, _crypto) are loaded by the absolute paths CMake
// took from Cyclone's imported targets at build time (common/dds/CMakeLists.txt): never a search at run time.
#pragma once

#include <string>
#include <vector>

#include "common/types.hpp"

namespace swarmform::dds {

struct SecurityFiles {
  std::string identity;  // the identity's name: "world", "robot-3", "observer"
  std::string ca;        // absolute paths
  std::string certificate;
  std::string private_key;
  std::string governance;
  std::string permissions;
};

// The identity names the launcher writes certificates for.
std::string world_identity();
std::string robot_identity(RobotId id);
std::string observer_identity();

// The files of `identity` in `dir`, checked: every file exists and is a readable regular file, and the
// private key is readable by its owner only (mode 0600 or 0400). Throws std::invalid_argument naming the file
// and what is wrong.
SecurityFiles security_files(const std::string& dir, const std::string& identity);

// The plugins' paths found at build time (authentication, access control, cryptography).
std::vector<std::string> security_plugins();

// The <Security> element for these files (authentication, access control, cryptography), to go inside
// <Domain>. Throws std::invalid_argument on a path Cyclone's XML cannot carry.
std::string security_config_xml(const SecurityFiles& files);

}  // namespace swarmform::dds
