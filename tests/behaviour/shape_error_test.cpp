// The shape error (docs/recording-format.md): the label grid fitted onto the robots by rotation + translation
// only.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "behaviour/shape_error.hpp"

namespace swarmform::shape_metrics {
namespace {

// The paper's triangle (Fig. 1): 6 labels in 3 rows.
ShapeMatrix triangle() {
  return ShapeMatrix{3, 5, {-1, -1, 0, -1, -1, -1, 1, -1, 2, -1, 3, -1, 4, -1, 5}};
}

// Robots standing exactly on the grid, rotated by `angle` about the origin and moved by `offset`.
std::vector<LabelledPosition> placed(const ShapeMatrix& shape, double spacing, double angle, Vec2 offset) {
  std::vector<LabelledPosition> robots;
  for (int row = 0; row < shape.rows; ++row) {
    for (int col = 0; col < shape.cols; ++col) {
      const int label = shape.at(row, col);
      if (label < 0) continue;
      const double x = col * spacing;
      const double y = -row * spacing;
      robots.push_back({label,
                        {std::cos(angle) * x - std::sin(angle) * y + offset.x,
                         std::sin(angle) * x + std::cos(angle) * y + offset.y}});
    }
  }
  return robots;
}

TEST(ShapeError, PerfectGridIsZeroUnderAnyRotationAndTranslation) {
  const auto shape = triangle();
  for (const double angle : {0.0, 0.3, 1.0, std::numbers::pi / 2, 2.5, -3.0, std::numbers::pi}) {
    for (const Vec2 offset : {Vec2{0, 0}, Vec2{5.5, -3.25}, Vec2{-100, 42}}) {
      const auto error = shape_error(shape, 1.4, placed(shape, 1.4, angle, offset));
      ASSERT_TRUE(error.has_value());
      EXPECT_LT(*error, 1e-9) << "angle " << angle;
    }
  }
}

TEST(ShapeError, KnownStretchOfTwoRobots) {
  // Labels 0 and 1 one grid apart (2 m); the robots stand 2.4 m apart: after the best fit each is 0.2 m off,
  // i.e. 0.1 grid units, whatever the direction the pair points in.
  const ShapeMatrix line{1, 2, {0, 1}};
  const std::vector<LabelledPosition> robots{{0, {3.0, 1.0}}, {1, {3.0, 3.4}}};
  const auto error = shape_error(line, 2.0, robots);
  ASSERT_TRUE(error.has_value());
  EXPECT_NEAR(*error, 0.1, 1e-12);
}

TEST(ShapeError, ScalingIsNotFittedAway) {
  // A 2x2 square scaled by 1.1 about its centre: every corner is 0.1 * (half diagonal) off after the fit.
  const ShapeMatrix square{2, 2, {0, 1, 2, 3}};
  auto robots = placed(square, 1.0, 0.7, {1.0, 2.0});
  Vec2 centre;
  for (const auto& r : robots) {
    centre.x += r.position.x / 4;
    centre.y += r.position.y / 4;
  }
  for (auto& r : robots) {
    r.position.x = centre.x + 1.1 * (r.position.x - centre.x);
    r.position.y = centre.y + 1.1 * (r.position.y - centre.y);
  }
  const auto error = shape_error(square, 1.0, robots);
  ASSERT_TRUE(error.has_value());
  EXPECT_NEAR(*error, 0.1 * std::sqrt(0.5), 1e-12);
}

TEST(ShapeError, MissingAndUnknownLabelsAreLeftOut) {
  const auto shape = triangle();
  auto robots = placed(shape, 1.0, 0.4, {2.0, -1.0});
  robots.erase(robots.begin() + 1);       // label 1 held by no robot
  robots.erase(robots.begin() + 3);       // nor label 4
  robots.push_back({-1, {50.0, 50.0}});   // a spare, far away
  robots.push_back({17, {-50.0, 50.0}});  // a label the shape does not have
  const auto error = shape_error(shape, 1.0, robots);
  ASSERT_TRUE(error.has_value());
  EXPECT_LT(*error, 1e-9);
}

TEST(ShapeError, FewerThanTwoRobotsHaveNoError) {
  const auto shape = triangle();
  EXPECT_FALSE(shape_error(shape, 1.0, {}).has_value());
  EXPECT_FALSE(shape_error(shape, 1.0, {{0, {1.0, 1.0}}, {-1, {2.0, 2.0}}}).has_value());
}

TEST(ShapeError, AMirroredFormationIsNotFittedByAReflection) {
  // An L: its mirror image cannot be reached by a rotation, so standing mirrored is a real error.
  const ShapeMatrix ell{3, 2, {0, -1, 1, -1, 2, 3}};
  auto robots = placed(ell, 1.0, 0.0, {0, 0});
  for (auto& r : robots) r.position.x = -r.position.x;  // reflect about the y axis
  const auto error = shape_error(ell, 1.0, robots);
  ASSERT_TRUE(error.has_value());
  EXPECT_GT(*error, 0.3);
  // ... while the same L merely rotated by pi fits exactly.
  const auto rotated = shape_error(ell, 1.0, placed(ell, 1.0, std::numbers::pi, {4, 4}));
  ASSERT_TRUE(rotated.has_value());
  EXPECT_LT(*rotated, 1e-9);
}

}  // namespace
}  // namespace swarmform::shape_metrics
