#include "robot_agent/controller/shape_table.hpp"

#include <cmath>
#include <mutex>
#include <numbers>

namespace swarmform::controller {

std::shared_ptr<const ShapeTable::Data> ShapeTable::build(const ShapeMatrix& shape, double spacing) {
  auto data = std::make_shared<Data>();
  data->shape = shape;
  data->spacing = spacing;
  const int n = shape.label_count();
  auto& rows = data->rows;
  auto& offsets = data->offsets;
  rows.assign(static_cast<std::size_t>(n), {});
  offsets.assign(static_cast<std::size_t>(n), {});
  const auto [r0, c0] = shape.cell_of(0);
  for (int r = 0; r < shape.rows; ++r) {
    for (int c = 0; c < shape.cols; ++c) {
      const int label = shape.at(r, c);
      if (label < 0 || label >= n) continue;
      offsets[static_cast<std::size_t>(label)] = {spacing * (c - c0), -spacing * (r - r0)};
      auto& row = rows[static_cast<std::size_t>(label)];
      for (int dr = -1; dr <= 1; ++dr) {
        for (int dc = -1; dc <= 1; ++dc) {
          const int rr = r + dr, cc = c + dc;
          if ((dr == 0 && dc == 0) || rr < 0 || cc < 0 || rr >= shape.rows || cc >= shape.cols) continue;
          const int other = shape.at(rr, cc);
          if (other < 0) continue;
          row.push_back({other, std::atan2(-static_cast<double>(dr), static_cast<double>(dc)),
                         spacing * std::hypot(static_cast<double>(dr), static_cast<double>(dc)), dr, dc});
        }
      }
    }
  }
  return data;
}

ShapeTable::ShapeTable(const ShapeMatrix& shape, double spacing) {
  // The tables built in this process, while any robot still holds one.
  static std::mutex mutex;
  static std::vector<std::weak_ptr<const Data>> built;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    std::erase_if(built, [](const auto& w) { return w.expired(); });
    for (const auto& w : built) {
      auto data = w.lock();
      if (data && data->spacing == spacing && data->shape.rows == shape.rows &&
          data->shape.cols == shape.cols && data->shape.cells == shape.cells) {
        data_ = std::move(data);
        break;
      }
    }
    if (!data_) {
      data_ = build(shape, spacing);
      built.push_back(data_);
    }
  }
}

const ShapeMatrix& ShapeTable::shape() const {
  static const ShapeMatrix kEmpty;
  return data_ ? data_->shape : kEmpty;
}

const std::vector<ShapeNeighbour>& ShapeTable::neighbours(int label) const {
  static const std::vector<ShapeNeighbour> kNone;
  if (label < 0 || label >= size()) return kNone;
  return data_->rows[static_cast<std::size_t>(label)];
}

bool ShapeTable::are_neighbours(int a, int b) const {
  for (const auto& nb : neighbours(a)) {
    if (nb.label == b) return true;
  }
  return false;
}

Vec2 ShapeTable::offset(int label) const {
  if (label < 0 || label >= size()) return {};
  return data_->offsets[static_cast<std::size_t>(label)];
}

Vec2 ShapeTable::place(int label, Vec2 origin, double shape_heading) const {
  const Vec2 o = offset(label);
  const double rot = shape_heading - std::numbers::pi / 2.0;
  const double c = std::cos(rot), s = std::sin(rot);
  return {origin.x + c * o.x - s * o.y, origin.y + s * o.x + c * o.y};
}

std::vector<Vec2> ShapeTable::places(Vec2 origin, double shape_heading) const {
  std::vector<Vec2> out;
  out.reserve(static_cast<std::size_t>(size()));
  for (int l = 0; l < size(); ++l) out.push_back(place(l, origin, shape_heading));
  return out;
}

}  // namespace swarmform::controller
