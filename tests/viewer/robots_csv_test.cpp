// The replay's robots.csv reader (viewer/robots_csv.hpp): a tick's rows found by a binary search over byte
// offsets, the last recorded tick <= the one asked, a half-written last line and unreadable rows left out,
// bad headers refused naming what.
#include "viewer/robots_csv.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>

namespace swarmform::viewer {
namespace {

constexpr const char* kHeader = "tick,id,x,y,theta,alive,state,label,parent,leader,net_force";

class RobotsCsvTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char dir[] = "/tmp/sf-robots-csv-XXXXXX";
    ASSERT_NE(mkdtemp(dir), nullptr);
    dir_ = dir;
    path_ = dir_ + "/robots.csv";
  }
  void TearDown() override {
    std::remove(path_.c_str());
    rmdir(dir_.c_str());
  }
  // Ticks first..last every `every`, `robots` rows each: x = tick, y = id, theta = tick * 1e-3.
  void write(std::uint64_t first, std::uint64_t last, std::uint64_t every, int robots,
             const std::string& tail = "", const std::string& header = kHeader) {
    std::ofstream f(path_);
    f << header << "\n";
    for (std::uint64_t t = first; t <= last; t += every) {
      for (int id = 0; id < robots; ++id) {
        f << t << "," << id << "," << t << "," << id << "," << static_cast<double>(t) * 1e-3 << ",1,"
          << (t % 7) << "," << id << ",-1," << (id == 0 ? 1 : 0) << ",0.5\n";
      }
    }
    f << tail;
  }
  std::string dir_, path_;
};

void expect_tick(const RecordedTick& r, std::uint64_t tick, int robots) {
  ASSERT_EQ(r.tick, tick);
  ASSERT_EQ(r.rows.size(), static_cast<std::size_t>(robots));
  for (int id = 0; id < robots; ++id) {
    const RecordedRow& row = r.rows[static_cast<std::size_t>(id)];
    EXPECT_EQ(row.id, static_cast<std::uint32_t>(id));
    EXPECT_DOUBLE_EQ(row.x, static_cast<double>(tick));
    EXPECT_DOUBLE_EQ(row.y, id);
    EXPECT_EQ(row.state, static_cast<std::int32_t>(tick % 7));
    EXPECT_EQ(row.label, id);
    EXPECT_EQ(row.leader, id == 0);
  }
}

TEST_F(RobotsCsvTest, EveryTickFoundByBinarySearchInFewReads) {
  write(0, 19999, 1, 9);  // ~6 MB
  RobotsCsv csv(path_, 9);
  EXPECT_EQ(csv.first_tick(), 0u);
  EXPECT_EQ(csv.last_tick(), 19999u);
  const double log2_size = std::log2(static_cast<double>(csv.size_bytes()));
  for (std::uint64_t t : {19999u, 0u, 10000u, 1u, 19998u, 12345u, 3u}) {
    const std::uint64_t reads = csv.reads(), bytes = csv.bytes_read();
    expect_tick(csv.read(t), t, 9);
    // A jump: a binary search (each probe a line: a couple of short reads) and the tick's rows, not a scan.
    EXPECT_LT(static_cast<double>(csv.reads() - reads), 6 * log2_size + 20) << "tick " << t;
    EXPECT_LT(csv.bytes_read() - bytes, csv.size_bytes() / 20) << "tick " << t;
  }
  EXPECT_EQ(csv.bad_rows(), 0u);
}

TEST_F(RobotsCsvTest, PlayingForwardReadsOnlyTheNextRows) {
  write(0, 999, 1, 5);
  RobotsCsv csv(path_, 5);
  expect_tick(csv.read(100), 100, 5);
  for (std::uint64_t t = 101; t < 200; ++t) {
    const std::uint64_t before = csv.reads();
    expect_tick(csv.read(t), t, 5);
    EXPECT_LE(csv.reads() - before, 3u) << "tick " << t;  // the next tick's first line, then its block
  }
}

TEST_F(RobotsCsvTest, ASkippedTickShowsTheLastRecordedBeforeIt) {
  write(10, 500, 5, 3);  // ticks 10, 15, ..., 500
  RobotsCsv csv(path_, 3);
  EXPECT_EQ(csv.first_tick(), 10u);
  EXPECT_EQ(csv.last_tick(), 500u);
  expect_tick(csv.read(17), 15, 3);
  expect_tick(csv.read(19), 15, 3);
  expect_tick(csv.read(20), 20, 3);
  expect_tick(csv.read(3), 10, 3);      // before the recording: its first tick
  expect_tick(csv.read(9999), 500, 3);  // after it: its last
  expect_tick(csv.read(12), 10, 3);     // backwards
}

TEST_F(RobotsCsvTest, AHalfWrittenLastLineIsNotData) {
  write(0, 50, 1, 4, "51,0,51,0,0.05");
  RobotsCsv csv(path_, 4);
  EXPECT_EQ(csv.last_tick(), 50u);
  expect_tick(csv.read(51), 50, 4);
  EXPECT_EQ(csv.bad_rows(), 0u);
}

TEST_F(RobotsCsvTest, AnUnreadableRowIsSkippedAndCountedWithItsOffset) {
  write(0, 20, 1, 3);
  {
    std::ofstream f(path_, std::ios::app);
    f << "21,0,21,0,0.021,1,0,0,-1,1,0.5\n21,1,oops,1,0.021,1,0,1,-1,0,0.5\n21,2,21,2,0.021,1,0,2,-1,0,0.5\n";
  }
  RobotsCsv csv(path_, 3);
  const RecordedTick& r = csv.read(21);
  EXPECT_EQ(r.tick, 21u);
  ASSERT_EQ(r.rows.size(), 2u);
  EXPECT_EQ(r.rows[0].id, 0u);
  EXPECT_EQ(r.rows[1].id, 2u);
  EXPECT_EQ(csv.bad_rows(), 1u);
  EXPECT_NE(csv.first_problem().find("robots.csv: the row at byte "), std::string::npos)
      << csv.first_problem();
  EXPECT_NE(csv.first_problem().find("oops"), std::string::npos) << csv.first_problem();
}

TEST_F(RobotsCsvTest, MoreRowsThanRobotsAreCountedNotKept) {
  write(0, 10, 1, 6);
  RobotsCsv csv(path_, 4);
  EXPECT_EQ(csv.read(5).rows.size(), 4u);
  EXPECT_EQ(csv.read(6).tick, 6u);
  EXPECT_GT(csv.bad_rows(), 0u);
}

TEST_F(RobotsCsvTest, TheBehavioursColumnsAndWordsForBooleans) {
  {
    std::ofstream f(path_);
    f << std::string(kHeader) << ",neighbours,speed\n"
      << "0,0,1.5,2.5,0.1,true,3,-1,-1,false,0.25,,\n"
      << "0,1,1.5,2.5,0.1,false,3,-1,-1,true,0.25,4,0.5\n";
  }
  RobotsCsv csv(path_, 2);
  ASSERT_EQ(csv.extra_columns(), (std::vector<std::string>{"neighbours", "speed"}));
  const RecordedTick& r = csv.read(0);
  ASSERT_EQ(r.rows.size(), 2u);
  EXPECT_TRUE(r.rows[0].alive);
  EXPECT_FALSE(r.rows[0].leader);
  EXPECT_TRUE(std::isnan(r.rows[0].extra[0]));
  EXPECT_FALSE(r.rows[1].alive);
  EXPECT_DOUBLE_EQ(r.rows[1].extra[0], 4.0);
  EXPECT_DOUBLE_EQ(r.rows[1].extra[1], 0.5);
}

// The LEDs' column is read into each row (off when empty) and is not one of the behaviour's columns; a row
// whose LEDs cannot be read is a bad row.
TEST_F(RobotsCsvTest, TheLedsColumnIsReadAndIsNotTelemetry) {
  {
    std::ofstream f(path_);
    f << std::string(kHeader) << ",leds,neighbours\n"
      << "0,0,1.5,2.5,0.1,1,3,-1,-1,0,0.25,,2\n"
      << "0,1,1.5,2.5,0.1,1,3,-1,-1,0,0.25,#00ff00 #000000 #0a0b0c,\n"
      << "1,0,1.5,2.5,0.1,1,3,-1,-1,0,0.25,#00ff00,2\n"
      << "1,1,1.5,2.5,0.1,1,3,-1,-1,0,0.25,,2\n";
  }
  RobotsCsv csv(path_, 2);
  ASSERT_EQ(csv.extra_columns(), (std::vector<std::string>{"neighbours"}));
  const RecordedTick& r = csv.read(0);
  ASSERT_EQ(r.rows.size(), 2u);
  EXPECT_EQ(r.rows[0].leds, (std::array<Rgb, kLedCount>{}));
  EXPECT_DOUBLE_EQ(r.rows[0].extra[0], 2.0);
  EXPECT_EQ(r.rows[1].leds, (std::array<Rgb, kLedCount>{Rgb{0, 255, 0}, Rgb{}, Rgb{10, 11, 12}}));
  EXPECT_TRUE(std::isnan(r.rows[1].extra[0]));
  EXPECT_EQ(csv.read(1).rows.size(), 1u);
  EXPECT_EQ(csv.bad_rows(), 1u);
}

// readings.csv (docs/recording-format.md): tick and id, then numbers; a dead robot's fields are empty (NaN),
// a field that is not a number makes its row unreadable; no robots.csv column is asked for.
TEST_F(RobotsCsvTest, AReadingsFileGivesEachRowsNumbers) {
  {
    std::ofstream f(path_);
    f << "tick,id,proximity0,lidar_rays,battery\n"
      << "0,0,0.25,682,1\n0,1,,,\n"
      << "5,0,0.5,682,0.75\n5,1,x,682,0.5\n";
  }
  EXPECT_THROW(RobotsCsv(path_, 2), std::runtime_error);  // not a robots.csv
  RobotsCsv csv(path_, 2, RowsFile::Readings);
  ASSERT_EQ(csv.extra_columns(), (std::vector<std::string>{"proximity0", "lidar_rays", "battery"}));
  EXPECT_EQ(csv.last_tick(), 5u);
  const RecordedTick& t0 = csv.read(3);  // the last recorded tick <= 3
  ASSERT_EQ(t0.tick, 0u);
  ASSERT_EQ(t0.rows.size(), 2u);
  EXPECT_EQ(t0.rows[0].extra, (std::vector<double>{0.25, 682, 1}));
  EXPECT_EQ(t0.rows[1].id, 1u);
  for (double v : t0.rows[1].extra) EXPECT_TRUE(std::isnan(v));
  const RecordedTick& t5 = csv.read(5);
  ASSERT_EQ(t5.rows.size(), 1u);
  EXPECT_EQ(t5.rows[0].extra, (std::vector<double>{0.5, 682, 0.75}));
  EXPECT_EQ(csv.bad_rows(), 1u);
}

TEST_F(RobotsCsvTest, BadFilesAreRefusedNamingWhat) {
  auto message = [&]() -> std::string {
    try {
      RobotsCsv csv(path_, 9);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "(accepted)";
  };
  EXPECT_NE(message().find("cannot open"), std::string::npos) << message();  // no file
  write(0, 3, 1, 2, "", "tick,id,x,y,theta,alive,state,label,parent,leader");
  EXPECT_NE(message().find(":1: the header lacks column(s) net_force"), std::string::npos) << message();
  write(0, 0, 1, 0);  // a header and nothing else
  EXPECT_NE(message().find("no complete row"), std::string::npos) << message();
  {
    std::ofstream f(path_);
    f << "no newline at all";
  }
  EXPECT_NE(message().find("no header line"), std::string::npos) << message();
}

}  // namespace
}  // namespace swarmform::viewer
