#include "common/dds/security_config.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <stdexcept>

#if !defined(SWARMFORM_DDS_SECURITY_AUTH) || !defined(SWARMFORM_DDS_SECURITY_AC) || \
    !defined(SWARMFORM_DDS_SECURITY_CRYPTO)
#error "the plugins' paths are set by common/dds/CMakeLists.txt (Cyclone's imported targets)"
#endif

namespace swarmform::dds {

namespace {

// The value goes into XML text as a file: URI. Paths with markup or URI-significant characters are refused
// rather than escaped: the launcher's run directories never have them.
void check_path(const std::string& path) {
  for (char c : path) {
    if (c == '<' || c == '>' || c == '&' || c == '"' || c == '\'' || c == '%' || c == '#' || c == '?' ||
        static_cast<unsigned char>(c) < 0x20) {
      throw std::invalid_argument("security file '" + path +
                                  "': its path has a character the Cyclone configuration cannot carry");
    }
  }
}

std::string checked_file(const std::string& dir, const std::string& name, bool is_key) {
  const std::string path = std::filesystem::absolute(std::filesystem::path(dir) / name).lexically_normal();
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    throw std::invalid_argument("security file '" + path + "' does not exist (is --security-dir '" + dir +
                                "' a directory made by `swarm run --secure`?)");
  }
  if (!S_ISREG(st.st_mode)) throw std::invalid_argument("security file '" + path + "' is not a regular file");
  if (::access(path.c_str(), R_OK) != 0)
    throw std::invalid_argument("security file '" + path + "' is not readable");
  if (is_key && (st.st_mode & (S_IRWXG | S_IRWXO)) != 0) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", static_cast<unsigned>(st.st_mode & 07777));
    throw std::invalid_argument("private key '" + path + "' has mode " + mode +
                                ": others than its owner may read it (want 0600)");
  }
  check_path(path);
  return path;
}

std::string library(const char* path, const char* init, const char* finalize) {
  return std::string("<Library path=\"") + path + "\" initFunction=\"" + init + "\" finalizeFunction=\"" +
         finalize + "\"/>";
}

}  // namespace

std::string world_identity() {
  return "world";
}
std::string robot_identity(RobotId id) {
  return "robot-" + std::to_string(id);
}
std::string observer_identity() {
  return "observer";
}

SecurityFiles security_files(const std::string& dir, const std::string& identity) {
  if (dir.empty()) throw std::invalid_argument("the security directory is empty");
  SecurityFiles f;
  f.identity = identity;
  f.ca = checked_file(dir, "ca.pem", false);
  f.governance = checked_file(dir, "governance.p7s", false);
  f.certificate = checked_file(dir, identity + ".pem", false);
  f.private_key = checked_file(dir, identity + ".key", true);
  f.permissions = checked_file(dir, identity + ".permissions.p7s", false);
  return f;
}

std::vector<std::string> security_plugins() {
  return {SWARMFORM_DDS_SECURITY_AUTH, SWARMFORM_DDS_SECURITY_AC, SWARMFORM_DDS_SECURITY_CRYPTO};
}

std::string security_config_xml(const SecurityFiles& f) {
  for (const std::string* p : {&f.ca, &f.certificate, &f.private_key, &f.governance, &f.permissions}) {
    check_path(*p);
  }
  std::string xml = "<Security><Authentication>";
  xml += library(SWARMFORM_DDS_SECURITY_AUTH, "init_authentication", "finalize_authentication");
  xml += "<IdentityCA>file:" + f.ca + "</IdentityCA>";
  xml += "<IdentityCertificate>file:" + f.certificate + "</IdentityCertificate>";
  xml += "<PrivateKey>file:" + f.private_key + "</PrivateKey>";
  xml += "</Authentication><AccessControl>";
  xml += library(SWARMFORM_DDS_SECURITY_AC, "init_access_control", "finalize_access_control");
  // One CA signs identities and documents alike: a run has one authority.
  xml += "<PermissionsCA>file:" + f.ca + "</PermissionsCA>";
  xml += "<Governance>file:" + f.governance + "</Governance>";
  xml += "<Permissions>file:" + f.permissions + "</Permissions>";
  xml += "</AccessControl><Cryptographic>";
  xml += library(SWARMFORM_DDS_SECURITY_CRYPTO, "init_crypto", "finalize_crypto");
  xml += "</Cryptographic></Security>";
  return xml;
}

}  // namespace swarmform::dds
