#include "world_server/world/floor.hpp"

#include <png.h>

#include <cmath>
#include <stdexcept>

namespace swarmform::world {

double grey_of(std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  return (0.299 * r + 0.587 * g + 0.114 * b) / 255.0;
}

namespace {

bool in_region(const FloorRegion& reg, double x, double y) {
  const double dx = x - reg.centre.x, dy = y - reg.centre.y;
  if (reg.kind == FloorRegion::Kind::Circle) return dx * dx + dy * dy <= reg.radius * reg.radius;
  const double c = std::cos(reg.yaw), s = std::sin(reg.yaw);
  const double u = c * dx + s * dy, v = -s * dx + c * dy;  // in the rectangle's frame
  return std::abs(u) <= reg.half_extents.x && std::abs(v) <= reg.half_extents.y;
}

}  // namespace

double floor_grey(const Floor& floor, Vec2 arena_centre, double width, double height, double x, double y) {
  for (auto it = floor.regions.rbegin(); it != floor.regions.rend(); ++it) {
    if (in_region(*it, x, y)) return it->grey;
  }
  if (floor.image) {
    const FloorImage& img = *floor.image;
    const double fx = (x - (arena_centre.x - width / 2.0)) / width;    // 0 at the left edge
    const double fy = ((arena_centre.y + height / 2.0) - y) / height;  // 0 at the top edge
    if (fx >= 0.0 && fx < 1.0 && fy >= 0.0 && fy < 1.0) {
      const auto col = std::min<std::uint32_t>(static_cast<std::uint32_t>(fx * img.width), img.width - 1);
      const auto row = std::min<std::uint32_t>(static_cast<std::uint32_t>(fy * img.height), img.height - 1);
      return img.grey[static_cast<std::size_t>(row) * img.width + col] / 255.0;
    }
  }
  return floor.grey;
}

FloorImage load_floor_image(const std::string& path) {
  // libpng's simplified API: it opens, checks and converts any PNG to 8-bit RGB for us.
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (png_image_begin_read_from_file(&image, path.c_str()) == 0) {
    throw std::runtime_error(std::string("cannot read it as a PNG: ") + image.message);
  }
  // A floor of more than 8192 pixels a side would cost memory and say nothing a coarser image does not.
  constexpr std::uint32_t kMaxSide = 8192;
  if (image.width == 0 || image.height == 0 || image.width > kMaxSide || image.height > kMaxSide) {
    const std::string size = std::to_string(image.width) + " x " + std::to_string(image.height);
    png_image_free(&image);
    throw std::runtime_error("is " + size + " pixels; a floor image has 1 to " + std::to_string(kMaxSide) +
                             " pixels a side");
  }
  image.format = PNG_FORMAT_RGB;
  std::vector<std::uint8_t> rgb(PNG_IMAGE_SIZE(image));
  if (png_image_finish_read(&image, nullptr, rgb.data(), 0, nullptr) == 0) {
    const std::string why = image.message;
    png_image_free(&image);
    throw std::runtime_error("cannot read it as a PNG: " + why);
  }
  FloorImage out;
  out.file = path;
  out.width = image.width;
  out.height = image.height;
  out.grey.resize(static_cast<std::size_t>(out.width) * out.height);
  for (std::size_t i = 0; i < out.grey.size(); ++i) {
    out.grey[i] =
        static_cast<std::uint8_t>(std::lround(255.0 * grey_of(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2])));
  }
  return out;
}

}  // namespace swarmform::world
