// The ground sensors and the floor: ARGoS's offsets against hand-computed points (a robot half on a black
// region), regions painted in order, colours made grey as ARGoS does, a PNG floor stretched over the arena,
// the floor's bad inputs refused at file:line, the noise's statistics, and the world computing the ground
// only for a behaviour that declares it.
#include "world_server/world/ground.hpp"

#include <gtest/gtest.h>
#include <png.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "common/input_error.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "test_scenarios.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::world {
namespace {

namespace fs = std::filesystem;

FloorRegion rectangle(double cx, double cy, double w, double h, double grey) {
  FloorRegion r;
  r.kind = FloorRegion::Kind::Rectangle;
  r.centre = Vec2{cx, cy};
  r.half_extents = Vec2{w / 2.0, h / 2.0};
  r.grey = grey;
  return r;
}

FloorRegion circle(double cx, double cy, double radius, double grey) {
  FloorRegion r;
  r.kind = FloorRegion::Kind::Circle;
  r.centre = Vec2{cx, cy};
  r.radius = radius;
  r.grey = grey;
  return r;
}

GroundReading read(const Floor& f, const Pose2D& pose) {
  return Ground(f, Vec2{0.0, 0.0}, 4.0, 4.0, 0.0, 1).read(pose);
}

TEST(Ground, RobotHalfOnABlackRegionSeesItWithItsLeftSensors) {
  Floor f;
  f.regions.push_back(rectangle(-1.0, 0.0, 2.0, 4.0, 0.0));  // x < 0 black, the rest the white floor
  // Facing +y: the robot's left is -x. ARGoS's offsets (x ahead, y left): (0.0614, 0.01) and (0.0206, 0.059)
  // land at x = -0.01 and -0.059 (black); (0.0206, -0.059) and (0.0614, -0.01) at x = 0.059 and 0.01 (white).
  EXPECT_EQ(read(f, Pose2D{0.0, 0.0, std::numbers::pi / 2.0}), (GroundReading{0.0, 0.0, 1.0, 1.0}));
  // Facing -y: the other way round.
  EXPECT_EQ(read(f, Pose2D{0.0, 0.0, -std::numbers::pi / 2.0}), (GroundReading{1.0, 1.0, 0.0, 0.0}));
  // Facing +x 1.5 cm from the edge: the sensors are all ahead of the centre (x >= 0.0206 - 0.015): all white.
  EXPECT_EQ(read(f, Pose2D{-0.015, 0.0, 0.0}), (GroundReading{1.0, 1.0, 1.0, 1.0}));
  // 3 cm back: the two rear sensors (x offset 0.0206) are on black, the front ones (0.0614) not.
  EXPECT_EQ(read(f, Pose2D{-0.03, 0.0, 0.0}), (GroundReading{1.0, 0.0, 0.0, 1.0}));
}

TEST(Ground, LaterRegionsLieOnTopAndColoursBecomeGreyAsInArgos) {
  Floor f;
  f.grey = 0.5;
  f.regions.push_back(circle(1.0, 1.0, 0.5, 0.0));
  f.regions.push_back(circle(1.0, 1.0, 0.2, grey_of(255, 0, 0)));
  EXPECT_NEAR(grey_of(255, 0, 0), 0.299, 1e-12);
  EXPECT_NEAR(grey_of(0, 255, 0), 0.587, 1e-12);
  EXPECT_EQ(read(f, Pose2D{1.0, 1.0, 0.0}), (GroundReading{0.299, 0.299, 0.299, 0.299}));
  EXPECT_EQ(read(f, Pose2D{1.3, 1.0, 0.0}), (GroundReading{0.0, 0.0, 0.0, 0.0}));
  EXPECT_EQ(read(f, Pose2D{-1.0, 0.0, 0.0}), (GroundReading{0.5, 0.5, 0.5, 0.5}));
}

TEST(Ground, NoiseIsUniformWithinTheLevelAndFollowsTheSeed) {
  Floor f;
  f.grey = 0.5;
  const std::vector<Pose2D> poses{Pose2D{0.0, 0.0, 0.0}};
  const std::vector<char> alive{1};
  Ground a(f, Vec2{}, 4.0, 4.0, 0.2, 9), b(f, Vec2{}, 4.0, 4.0, 0.2, 9), c(f, Vec2{}, 4.0, 4.0, 0.2, 10);
  std::vector<GroundReading> ra, rb, rc;
  double sum = 0.0, sum2 = 0.0, lo = 1.0, hi = 0.0;
  bool differs = false;
  constexpr int kDraws = 2000;
  for (int i = 0; i < kDraws; ++i) {
    a.sense_all(poses, alive, ra);
    b.sense_all(poses, alive, rb);
    c.sense_all(poses, alive, rc);
    ASSERT_EQ(ra, rb);
    differs = differs || ra != rc;
    for (double v : ra[0]) {
      sum += v - 0.5;
      sum2 += (v - 0.5) * (v - 0.5);
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  EXPECT_TRUE(differs);
  const double n = 4.0 * kDraws;
  EXPECT_NEAR(sum / n, 0.0, 0.01);
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.2 / std::sqrt(3.0), 0.006);
  EXPECT_GE(lo, 0.3);
  EXPECT_LE(hi, 0.7);
  EXPECT_LT(lo, 0.31);
  EXPECT_GT(hi, 0.69);
}

// A scratch folder with a scenario and its floor image.
class FloorFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("swarmform-floor-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A w x h RGB PNG whose top-left pixel is black and the rest white.
  void write_png(const std::string& name, std::uint32_t w, std::uint32_t h) {
    std::vector<std::uint8_t> rgb(3u * w * h, 255);
    rgb[0] = rgb[1] = rgb[2] = 0;
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    image.width = w;
    image.height = h;
    image.format = PNG_FORMAT_RGB;
    ASSERT_NE(png_image_write_to_file(&image, (dir_ / name).c_str(), 0, rgb.data(), 0, nullptr), 0);
  }
  std::string scenario(const std::string& floor) {
    const fs::path p = dir_ / "s.yaml";
    std::ofstream(p) << "behaviour: diffusion\narena: {centre: [0, 0], width: 4, height: 4}\n"
                     << "robots: {poses: [[-1, 1, 0], [1, 1, 0]]}\n"
                     << floor;
    return p.string();
  }
  Scenario load(const std::string& floor) {
    return load_scenario(scenario(floor), {}, controller::builtin_registry());
  }
  void refused(const std::string& floor, int line, const std::string& what) {
    try {
      (void)load(floor);
      ADD_FAILURE() << "accepted: " << floor;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), (dir_ / "s.yaml").string());
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  }
  fs::path dir_;
};

TEST_F(FloorFiles, ImageIsStretchedOverTheArenaAndRegionsLieOnIt) {
  write_png("floor.png", 2, 2);  // each pixel a 2 m x 2 m quarter of the arena; the top-left one black
  const Scenario s = load(
      "floor:\n  image: floor.png\n  regions:\n    - {type: circle, centre: [1, -1], radius: 0.5, "
      "colour: [0, 255, 0]}\n");
  ASSERT_NE(s.floor.image, nullptr);
  EXPECT_EQ(s.floor.image->width, 2u);
  // The region's colour is kept for pictures (the sensors read its grey).
  ASSERT_EQ(s.floor.regions.size(), 1u);
  EXPECT_EQ(s.floor.regions[0].colour, (Rgb{0, 255, 0}));
  EXPECT_FALSE(s.floor.colour.has_value());
  auto at = [&](double x, double y) { return floor_grey(s.floor, s.arena_centre, 4.0, 4.0, x, y); };
  EXPECT_EQ(at(-1.0, 1.0), 0.0);
  EXPECT_EQ(at(1.0, 1.0), 1.0);
  EXPECT_EQ(at(-1.0, -1.0), 1.0);
  EXPECT_NEAR(at(1.0, -1.0), 0.587, 1e-12);
  EXPECT_EQ(at(5.0, 5.0), 1.0);  // off the image: the floor's grey (white by default)
  // And the robots standing on it read it through the world.
  World w(s);
  EXPECT_EQ(w.perception(0).ground, (GroundReading{0.0, 0.0, 0.0, 0.0}));
  EXPECT_EQ(w.perception(1).ground, (GroundReading{1.0, 1.0, 1.0, 1.0}));
}

TEST_F(FloorFiles, BadFloorsAreRefusedAtTheirLine) {
  write_png("wide.png", 4, 2);
  refused("floor:\n  image: missing.png\n", 5, "missing.png");
  refused("floor:\n  image: wide.png\n", 5, "4 x 2 pixels, but the arena is 4 x 4 m");
  std::ofstream(dir_ / "text.png") << "not a picture\n";
  refused("floor:\n  image: text.png\n", 5, "cannot read it as a PNG");
  refused("floor:\n  grey: 2\n", 5, "floor.grey");
  refused("floor:\n  grey: 0.5\n  colour: [1, 2, 3]\n", 5, "not both");
  refused("floor:\n  regions:\n    - {type: circle, centre: [0, 0], radius: 1}\n", 6, "missing 'grey'");
  refused("floor:\n  regions:\n    - {type: blob, centre: [0, 0], grey: 0}\n", 6, "circle or rectangle");
  refused("floor:\n  regions:\n    - {type: circle, centre: [0, 0], radius: 1, colour: [0, 0, 256]}\n", 6,
          "0..255");
  refused("floor:\n  pattern: stripes\n", 5, "floor.pattern: unknown key");
}

TEST(Ground, WorldFillsItOnlyForABehaviourThatDeclaresIt) {
  Scenario s = testing::open_scenario({Pose2D{0.0, 0.0, std::numbers::pi / 2.0}});
  s.floor.regions.push_back(rectangle(-1.0, 0.0, 2.0, 4.0, 0.0));
  s.behaviour = &controller::random_walk_descriptor();
  EXPECT_FALSE(World(s).perception(0).ground.has_value());
  const behaviour::Descriptor* diffusion = controller::builtin_registry().find("diffusion");
  ASSERT_NE(diffusion, nullptr);
  s.behaviour = diffusion;
  World w(s);
  EXPECT_EQ(w.perception(0).ground, (GroundReading{0.0, 0.0, 1.0, 1.0}));
  w.step();
  EXPECT_TRUE(w.perception(0).ground.has_value());
}

}  // namespace
}  // namespace swarmform::world
