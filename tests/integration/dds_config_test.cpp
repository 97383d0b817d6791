// The user's Cyclone configuration merged on top of ours (--dds-config FILE, else CYCLONEDDS_URI;
// docs/dds-config.md point 3): which source wins, the errors for a missing, empty, non-XML file or a list,
// the listing that
// --print-dds-config prints, and that Cyclone really merges it: a participant made with a user file that
// turns tracing on traces the user's setting as coming from the second document and ours from the first
// (test domain 58).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "common/dds/cyclone_config.hpp"
#include "common/dds/participant.hpp"
#include "tests/support/test_domain.hpp"

namespace {

namespace fs = std::filesystem;
using swarmform::dds::DdsSettings;
using swarmform::dds::user_dds_config;

class DdsConfig : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("sf-dds-config-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p.string();
  }
  static std::string error_of(const std::string& flag, const char* env) {
    try {
      (void)user_dds_config(flag, env);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "(no error)";
  }
  fs::path dir_;
};

const char* const kTuning =
    "<CycloneDDS><Domain><General><MaxMessageSize>8000B</MaxMessageSize></General></Domain></CycloneDDS>";

TEST_F(DdsConfig, TheFlagWinsOverTheEnvironmentAndNeitherMeansNone) {
  const std::string file = write("a.xml", kTuning);
  EXPECT_FALSE(user_dds_config("", nullptr).has_value());
  EXPECT_FALSE(user_dds_config("", "  ").has_value());
  const auto from_flag = user_dds_config(file, "<CycloneDDS><Domain/></CycloneDDS>");
  ASSERT_TRUE(from_flag.has_value());
  EXPECT_EQ(from_flag->source, "--dds-config " + file);
  EXPECT_EQ(from_flag->xml, kTuning);
  const auto from_uri = user_dds_config("", ("file://" + file).c_str());
  ASSERT_TRUE(from_uri.has_value());
  EXPECT_EQ(from_uri->source, "CYCLONEDDS_URI " + file);
  EXPECT_EQ(user_dds_config("", file.c_str())->xml, kTuning);  // a bare path
  EXPECT_EQ(user_dds_config("", kTuning)->source, "CYCLONEDDS_URI (inline)");
}

TEST_F(DdsConfig, BadFilesAreRefusedNamingTheSourceAndWhy) {
  const std::string missing = (dir_ / "missing.xml").string();
  EXPECT_EQ(error_of(missing, nullptr), "--dds-config " + missing + ": no such file");
  EXPECT_EQ(error_of("", missing.c_str()), "CYCLONEDDS_URI " + missing + ": no such file");
  EXPECT_NE(error_of(dir_.string(), nullptr).find(": is a directory"), std::string::npos);
  EXPECT_NE(error_of(write("empty.xml", " \n"), nullptr).find(": is empty"), std::string::npos);
  EXPECT_NE(
      error_of(write("text.xml", "MaxMessageSize=8000"), nullptr).find("is not a Cyclone DDS configuration"),
      std::string::npos);
  EXPECT_NE(error_of("", "a.xml,b.xml").find("a list of configurations is not taken here"),
            std::string::npos);
  EXPECT_NE(error_of("", "<Domain/>").find("root element <CycloneDDS>"), std::string::npos);
}

TEST_F(DdsConfig, TheListingShowsOursIndentedThenTheUsersInMergeOrder) {
  DdsSettings s;
  s.domain = 9;
  s.world_host = "10.1.2.3";
  const std::string alone = swarmform::dds::cyclone_config_listing(s, "robot_agent");
  EXPECT_NE(alone.find("robot_agent on DDS domain 9"), std::string::npos);
  EXPECT_NE(alone.find("1 of 1: swarmform's own"), std::string::npos);
  EXPECT_NE(alone.find("\n      <Peers>\n        <Peer address=\"10.1.2.3:8310\"/>\n"), std::string::npos);
  EXPECT_NE(alone.find("\n      <ParticipantIndex>none</ParticipantIndex>\n"), std::string::npos);
  s.user = user_dds_config(write("u.xml", kTuning), nullptr);
  const std::string both = swarmform::dds::cyclone_config_listing(s, "robot_agent");
  const std::size_t ours = both.find("1 of 2: swarmform's own");
  const std::size_t theirs = both.find("2 of 2: from --dds-config ");
  ASSERT_NE(ours, std::string::npos);
  ASSERT_NE(theirs, std::string::npos);
  EXPECT_LT(ours, theirs);
  EXPECT_NE(both.find(kTuning, theirs), std::string::npos);
  EXPECT_EQ(swarmform::dds::cyclone_config_string(s), swarmform::dds::cyclone_config_xml(s) + "," + kTuning);
}

TEST_F(DdsConfig, CycloneMergesTheUsersDocumentOnTopOfOurs) {
  const std::string trace = (dir_ / "trace.log").string();
  DdsSettings s;
  s.domain = static_cast<std::uint32_t>(swarmform::testing::test_domain(58));
  s.user = user_dds_config(write("trace.xml",
                                 "<CycloneDDS><Domain><General><MaxMessageSize>8000B</MaxMessageSize>"
                                 "</General><Tracing><Verbosity>config</Verbosity><OutputFile>" +
                                     trace + "</OutputFile></Tracing></Domain></CycloneDDS>"),
                           nullptr);
  { swarmform::dds::Participant p(s); }
  std::ifstream in(trace);
  ASSERT_TRUE(in) << "Cyclone wrote no trace: the user's <Tracing> was not applied";
  std::stringstream text;
  text << in.rdbuf();
  // {1}: set by the second document (the user's); {0}: by the first (ours).
  EXPECT_NE(text.str().find("Domain/General/MaxMessageSize/#text: 8000 B {1}"), std::string::npos)
      << text.str();
  EXPECT_NE(text.str().find("Domain/General/MaxRexmitMessageSize/#text: 14720 B {0}"), std::string::npos);
  EXPECT_NE(text.str().find("Domain/Discovery/ParticipantIndex/#text: none {0}"), std::string::npos);
}

TEST_F(DdsConfig, AConfigurationCycloneRefusesIsAnErrorNamingTheUsersFile) {
  DdsSettings s;
  s.domain = static_cast<std::uint32_t>(swarmform::testing::test_domain(58));
  s.user = user_dds_config(
      write("bad.xml",
            "<CycloneDDS><Domain><General><NoSuchSetting>1</NoSuchSetting></General></Domain></CycloneDDS>"),
      nullptr);
  try {
    swarmform::dds::Participant p(s);
    FAIL() << "Cyclone took an unknown setting";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("the configuration of --dds-config "), std::string::npos)
        << e.what();
  }
}

}  // namespace
