// The arena's floor as the ground sensors see it: a grey level (0 black .. 1 white) at every point. A base
// level, optionally an image stretched over the arena's rectangle, then coloured regions (circles and
// rectangles) painted over it in the order given. Colours become grey as ARGoS's CColor::ToGrayScale does
// (0.299 R + 0.587 G + 0.114 B, over 255). Immutable once loaded (part of the Scenario).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/types.hpp"

namespace swarmform::world {

struct FloorRegion {
  enum class Kind { Circle, Rectangle };
  Kind kind = Kind::Circle;
  Vec2 centre;        // m
  double radius = 0;  // m (circles)
  Vec2 half_extents;  // m (rectangles)
  double yaw = 0.0;   // rad (rectangles)
  double grey = 0.0;  // 0..1
  // The colour the scenario gave, if it gave one rather than a grey: only for pictures (the sensors read
  // `grey`).
  std::optional<Rgb> colour;
};

// Pixels in rows from the top (+y edge of the arena) down, each a grey level 0..255.
struct FloorImage {
  std::string file;  // as resolved, for the log
  std::uint32_t width = 0, height = 0;
  std::vector<std::uint8_t> grey;
};

struct Floor {
  double grey = 1.0;                        // outside the image and every region
  std::optional<Rgb> colour;                // as FloorRegion::colour
  std::shared_ptr<const FloorImage> image;  // null: none (shared: a Scenario is copied)
  std::vector<FloorRegion> regions;         // painted over the image, later ones on top

  bool plain() const { return image == nullptr && regions.empty(); }
};

// 0..1 from an 8-bit colour, as ARGoS's CColor::ToGrayScale.
double grey_of(std::uint8_t r, std::uint8_t g, std::uint8_t b);

// The floor's grey level at (x, y) in an arena centred at `arena_centre`, `width` x `height` m (the image's
// rectangle).
double floor_grey(const Floor& floor, Vec2 arena_centre, double width, double height, double x, double y);

// Reads a PNG (any bit depth and colour type; alpha ignored) into grey levels with libpng. Throws
// std::runtime_error saying what is wrong (missing, not a PNG, corrupt) on failure.
FloorImage load_floor_image(const std::string& path);

}  // namespace swarmform::world
