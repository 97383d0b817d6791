// The replay's robots.csv reader (viewer/robots_csv.hpp): a tick's rows found by a binary search over byte
// offsets, the last recorded tick <= the one asked, a half-written last line and unreadable rows left out,
// bad headers refused naming what.
#include "viewer/robots_csv.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
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

// The damage a viewer must say (robots_csv.hpp Damage): the tail of a killed run's file is found at open and
// the recording ends at its last whole tick; damage in the middle is found reading the ticks it touches.
TEST_F(RobotsCsvTest, ACutFileEndsAtItsLastWholeTickAndSaysSoAtOpen) {
  write(0, 50, 1, 4, "51,0,51,0,0.051,1,2,0,-1,1,0.5\n51,1,51,1,0.051,1,2,1,-1,0,0.5\n51,2,51,2,0.0");
  RobotsCsv csv(path_, 4, RowsFile::Robots, true);
  EXPECT_EQ(csv.last_tick(), 50u);
  ASSERT_EQ(csv.damage().size(), 1u);
  const Damage& d = csv.damage()[0];
  EXPECT_TRUE(d.at_open);
  EXPECT_EQ(d.from_tick, 50u);
  for (const char* part : {"ends early", "a half-written last line at byte ", "the last tick 51 has 2 of 4",
                           "shown up to tick 50"}) {
    EXPECT_NE(d.what.find(part), std::string::npos) << part << " not in: " << d.what;
  }
  expect_tick(csv.read(51), 50, 4);
  expect_tick(csv.read(50), 50, 4);
  EXPECT_EQ(csv.damage_at(50).size(), 1u);
  EXPECT_TRUE(csv.damage_at(49).empty());
  // Cut at a line's end inside a tick: the same without the half-written line.
  write(0, 50, 1, 4, "51,0,51,0,0.051,1,2,0,-1,1,0.5\n");
  RobotsCsv cut(path_, 4, RowsFile::Robots, true);
  EXPECT_EQ(cut.last_tick(), 50u);
  ASSERT_EQ(cut.damage().size(), 1u);
  EXPECT_EQ(cut.damage()[0].what.find("half-written"), std::string::npos) << cut.damage()[0].what;
  // A whole file: nothing said.
  write(0, 50, 1, 4);
  RobotsCsv whole(path_, 4, RowsFile::Robots, true);
  EXPECT_EQ(whole.last_tick(), 50u);
  EXPECT_TRUE(whole.damage().empty());
}

TEST_F(RobotsCsvTest, CorruptBytesInTheMiddleAreDamageAtTheTicksTheyTouch) {
  write(0, 200, 1, 4);
  std::string text;
  {
    std::ifstream f(path_, std::ios::binary);
    text.assign(std::istreambuf_iterator<char>(f), {});
  }
  // Bytes overwritten from inside tick 100's row of robot 2 to inside tick 103's row of robot 1 (no newline
  // among them): those two lines become one unreadable line, ticks 101 and 102 are lost.
  const std::size_t at = text.find("\n100,2,") + 4, n = text.find("\n103,1,") + 5 - at;
  const std::size_t bad_start = text.rfind('\n', at) + 1;
  const std::size_t bad_end = text.find('\n', at + n) + 1;
  const std::uint64_t a = 100, b = 103;
  text.replace(at, n, std::string(n, 'x'));
  {
    std::ofstream f(path_, std::ios::binary | std::ios::trunc);
    f << text;
  }
  RobotsCsv csv(path_, 4, RowsFile::Robots, true);
  EXPECT_EQ(csv.last_tick(), 200u);
  EXPECT_TRUE(csv.damage().empty()) << "nothing scanned at open: " << csv.damage()[0].what;
  expect_tick(csv.read(a - 3), a - 3, 4);
  EXPECT_TRUE(csv.damage_at(a - 3).empty());
  // A seek into the lost ticks: the last readable tick before them, and the damage that says why.
  const RecordedTick& r = csv.read(a + 1);
  EXPECT_EQ(r.tick, a);
  EXPECT_EQ(r.rows.size(), 2u);
  const std::vector<Damage> here = csv.damage_at(a + 1);
  ASSERT_EQ(here.size(), 1u);
  EXPECT_EQ(here[0].offset, bad_start);
  EXPECT_EQ(here[0].from_tick, a);
  EXPECT_EQ(here[0].to_tick, b - 1);
  for (const std::string& part :
       {"bytes " + std::to_string(bad_start) + ".." + std::to_string(bad_end) + " cannot be read (1 line(s)",
        "no tick after " + std::to_string(a) + " can be read before tick " + std::to_string(b),
        "tick " + std::to_string(a) + " has "}) {
    EXPECT_NE(here[0].what.find(part), std::string::npos) << part << " not in: " << here[0].what;
  }
  EXPECT_EQ(csv.damage_at(b - 1).size(), 1u);
  // The first tick after them lost its first rows: said from that tick.
  EXPECT_EQ(csv.read(b).tick, b);
  const std::vector<Damage> after = csv.damage_at(b);
  ASSERT_EQ(after.size(), 1u);
  EXPECT_NE(after[0].what.find("tick " + std::to_string(b) + " has "), std::string::npos) << after[0].what;
  EXPECT_TRUE(csv.damage_at(b + 1).empty());
  expect_tick(csv.read(b + 1), b + 1, 4);
  EXPECT_EQ(csv.damage().size(), 2u) << "each damage said once, however often read";
  csv.read(a + 1);
  EXPECT_EQ(csv.damage().size(), 2u);
}

TEST_F(RobotsCsvTest, ATickWithoutARobotSaysWhichIsMissing) {
  write(0, 30, 1, 4);
  std::string text;
  {
    std::ifstream f(path_, std::ios::binary);
    text.assign(std::istreambuf_iterator<char>(f), {});
  }
  const std::string row = "\n12,2,";
  const std::size_t at = text.find(row) + 1;
  text.erase(at, text.find('\n', at) + 1 - at);
  {
    std::ofstream f(path_, std::ios::binary | std::ios::trunc);
    f << text;
  }
  RobotsCsv csv(path_, 4, RowsFile::Robots, true);
  EXPECT_EQ(csv.read(12).rows.size(), 3u);
  const std::vector<Damage> d = csv.damage_at(12);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_NE(d[0].what.find("tick 12 has 3 of 4 robots' rows (missing: 2)"), std::string::npos) << d[0].what;
  EXPECT_TRUE(csv.damage_at(11).empty());
  EXPECT_TRUE(csv.damage_at(13).empty());
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
