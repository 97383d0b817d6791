// The shape table against the paper's Table II, and label places in the arena.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "common/shape.hpp"
#include "robot_agent/controller/shape_table.hpp"

namespace swarmform::controller {
namespace {

constexpr double kPi = std::numbers::pi;

ShapeTable triangle(double spacing) {
  return ShapeTable(load_shape_file(std::string(SWARMFORM_SHAPES_DIR) + "/triangle.txt"), spacing);
}

TEST(ShapeTable, TriangleLabelZeroRowIsTableTwo) {
  // Table II: label 0 -> neighbours 1, 2, 3 at -3pi/4, pi/2 (printed; -pi/2 here, see shapes/README.md),
  // -pi/4 and 1.4, 1.0, 1.4 m with the default spacing of 1 m.
  const auto table = triangle(1.0);
  const auto& row = table.neighbours(0);
  ASSERT_EQ(row.size(), 3u);
  EXPECT_EQ(row[0].label, 1);
  EXPECT_EQ(row[1].label, 2);
  EXPECT_EQ(row[2].label, 3);
  EXPECT_NEAR(row[0].angle, -3.0 * kPi / 4.0, 1e-12);
  EXPECT_NEAR(row[1].angle, -kPi / 2.0, 1e-12);
  EXPECT_NEAR(row[2].angle, -kPi / 4.0, 1e-12);
  EXPECT_NEAR(row[0].distance, 1.4, 0.015);
  EXPECT_NEAR(row[1].distance, 1.0, 1e-12);
  EXPECT_NEAR(row[2].distance, 1.4, 0.015);
}

TEST(ShapeTable, DistancesScaleWithTheMissionSpacing) {
  const auto table = triangle(0.5);
  EXPECT_NEAR(table.neighbours(0)[0].distance, 0.5 * std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(table.neighbours(0)[1].distance, 0.5, 1e-12);
}

// Tables of equal shapes and spacings share one copy in the process (shape_table.hpp); a table of another
// shape of the same size, or of another spacing, is its own.
TEST(ShapeTable, TablesShareOnlyWhatIsEqual) {
  ShapeMatrix line{1, 3, {0, 1, 2}};
  ShapeMatrix turned{1, 3, {1, 0, 2}};  // same size, other cells
  const ShapeTable a(line, 1.0), b(line, 1.0), c(turned, 1.0), d(line, 2.0);
  EXPECT_EQ(&a.neighbours(0), &b.neighbours(0));
  EXPECT_EQ(a.shape().cells, line.cells);
  // Label 0 in the middle of `turned`: two neighbours; at the end of `line`: one.
  ASSERT_EQ(a.neighbours(0).size(), 1u);
  ASSERT_EQ(c.neighbours(0).size(), 2u);
  EXPECT_EQ(c.shape().cells, turned.cells);
  EXPECT_NEAR(a.offset(2).x, 2.0, 1e-12);
  EXPECT_NEAR(c.offset(2).x, 1.0, 1e-12);
  EXPECT_NEAR(d.offset(2).x, 4.0, 1e-12);
  EXPECT_NEAR(d.neighbours(0)[0].distance, 2.0, 1e-12);
  EXPECT_EQ(d.spacing(), 2.0);
  // A copy and an empty table.
  const ShapeTable copy = c;
  EXPECT_EQ(copy.size(), 3);
  EXPECT_EQ(&copy.neighbours(1), &c.neighbours(1));
  const ShapeTable empty;
  EXPECT_EQ(empty.size(), 0);
  EXPECT_TRUE(empty.neighbours(0).empty());
  EXPECT_EQ(empty.shape().rows, 0);
}

TEST(ShapeTable, RowsAreSymmetric) {
  const auto table = triangle(1.0);
  for (int a = 0; a < table.size(); ++a) {
    for (const auto& nb : table.neighbours(a)) {
      bool back = false;
      for (const auto& other : table.neighbours(nb.label)) {
        if (other.label == a) {
          back = true;
          EXPECT_NEAR(std::abs(std::remainder(other.angle - nb.angle, 2 * kPi)), kPi, 1e-12);
          EXPECT_NEAR(other.distance, nb.distance, 1e-12);
        }
      }
      EXPECT_TRUE(back) << a << " -> " << nb.label;
    }
  }
  // Label 6 (middle of the bottom row) has 5 neighbours: 1, 2, 3 above, 5 and 7 beside.
  EXPECT_EQ(table.neighbours(6).size(), 5u);
  EXPECT_TRUE(table.are_neighbours(6, 2));
  EXPECT_FALSE(table.are_neighbours(0, 6));
}

TEST(ShapeTable, PlacesFollowTheShapeHeading) {
  const auto table = triangle(1.0);
  const Vec2 origin{2.0, -1.0};
  // Default heading pi/2: the shape frame is the arena frame, label 2 straight below label 0.
  const Vec2 p2 = table.place(2, origin, kPi / 2.0);
  EXPECT_NEAR(p2.x, 2.0, 1e-12);
  EXPECT_NEAR(p2.y, -2.0, 1e-12);
  EXPECT_NEAR(table.place(0, origin, kPi / 2.0).x, 2.0, 1e-12);
  // Heading 0 (the apex pointing along +x): label 2 is behind label 0, along -x; label 1 (left of 2 in the
  // matrix) is on the robot's left, +y.
  const Vec2 q2 = table.place(2, origin, 0.0);
  EXPECT_NEAR(q2.x, 1.0, 1e-12);
  EXPECT_NEAR(q2.y, -1.0, 1e-12);
  const Vec2 q1 = table.place(1, origin, 0.0);
  EXPECT_NEAR(q1.x, 1.0, 1e-12);
  EXPECT_NEAR(q1.y, 0.0, 1e-12);
  EXPECT_EQ(table.places(origin, 0.0).size(), 9u);
}

}  // namespace
}  // namespace swarmform::controller
