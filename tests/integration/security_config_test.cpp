// The <Security> section of the Cyclone configuration and the checks on an identity's files
// (common/dds/security_config.hpp; docs/security.md). Plain files in a temporary directory: no DDS.
#include "common/dds/security_config.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "common/dds/cyclone_config.hpp"

namespace {

namespace fs = std::filesystem;
using namespace swarmform::dds;

// A directory with the files of `robot-3` (contents do not matter here), removed at the end.
struct SecurityDir {
  fs::path dir;
  SecurityDir() {
    char tmpl[] = "/tmp/sf-security-test-XXXXXX";
    dir = ::mkdtemp(tmpl);
    for (const char* name :
         {"ca.pem", "governance.p7s", "robot-3.pem", "robot-3.key", "robot-3.permissions.p7s"}) {
      std::ofstream(dir / name) << "x\n";
    }
    ::chmod((dir / "robot-3.key").c_str(), 0600);
  }
  ~SecurityDir() { fs::remove_all(dir); }
};

std::string refusal(const SecurityDir& d) {
  try {
    (void)security_files(d.dir.string(), robot_identity(3));
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(SecurityConfig, TheSectionLoadsThePluginsFoundAtBuildTimeAndNamesTheIdentitysFiles) {
  SecurityDir d;
  const SecurityFiles f = security_files(d.dir.string(), robot_identity(3));
  EXPECT_EQ(f.identity, "robot-3");
  const std::string xml = security_config_xml(f);
  ASSERT_EQ(security_plugins().size(), 3u);
  for (const std::string& plugin : security_plugins()) {
    EXPECT_TRUE(fs::path(plugin).is_absolute()) << plugin;
    EXPECT_TRUE(fs::exists(plugin)) << plugin << " (compiled in from Cyclone's CMake targets)";
    EXPECT_NE(xml.find("<Library path=\"" + plugin + "\""), std::string::npos) << plugin;
  }
  for (const char* name :
       {"ca.pem", "robot-3.pem", "robot-3.key", "governance.p7s", "robot-3.permissions.p7s"}) {
    EXPECT_NE(xml.find("file:" + (d.dir / name).string() + "<"), std::string::npos) << name;
  }

  DdsSettings s;
  s.domain = 7;
  EXPECT_EQ(cyclone_config_xml(s).find("<Security>"), std::string::npos);
  s.security = f;
  const std::string full = cyclone_config_xml(s);
  const auto at = full.find("<Security>");
  ASSERT_NE(at, std::string::npos);
  EXPECT_LT(at, full.find("</Domain>"));
}

TEST(SecurityConfig, AKeyOthersMayReadIsRefusedNamingItsMode) {
  SecurityDir d;
  ::chmod((d.dir / "robot-3.key").c_str(), 0640);
  const std::string why = refusal(d);
  EXPECT_NE(why.find((d.dir / "robot-3.key").string()), std::string::npos) << why;
  EXPECT_NE(why.find("has mode 0640"), std::string::npos) << why;
  ::chmod((d.dir / "robot-3.key").c_str(), 0400);
  EXPECT_EQ(refusal(d), "");
}

TEST(SecurityConfig, AMissingFileOrAnotherIdentityIsNamed) {
  SecurityDir d;
  fs::remove(d.dir / "governance.p7s");
  EXPECT_NE(refusal(d).find("governance.p7s' does not exist"), std::string::npos) << refusal(d);
  EXPECT_THROW((void)security_files(d.dir.string(), robot_identity(4)), std::invalid_argument);
  EXPECT_THROW((void)security_files("", robot_identity(3)), std::invalid_argument);
}

TEST(SecurityConfig, APathTheXmlCannotCarryIsRefused) {
  SecurityDir d;
  SecurityFiles f = security_files(d.dir.string(), robot_identity(3));
  f.certificate = "/tmp/a<b>.pem";
  EXPECT_THROW((void)security_config_xml(f), std::invalid_argument);
}

}  // namespace
