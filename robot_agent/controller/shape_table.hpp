// The shape table (paper III.B, Table II): for each label, the labels of its 8 neighbours in the matrix with
// their angle and distance, and each label's place.
//
// Angles are in the shape's own frame: column along +x, row along -y (common/shape.hpp), so the neighbour at
// grid offset (drow, dcol) lies at atan2(-drow, dcol), spacing * hypot(drow, dcol) away. Neighbours are
// listed in the order the 3x3 grid is scanned (row by row, left to right), as Table II lists 1, 2, 3.
// In the arena the shape frame is turned so that its +y ("up", towards row 0) points along shape_heading:
// arena = R(shape_heading - pi/2) * shape frame.
#pragma once

#include <vector>

#include "common/shape.hpp"
#include "common/types.hpp"

namespace swarmform::controller {

struct ShapeNeighbour {
  int label = -1;
  double angle = 0.0;     // rad, shape frame
  double distance = 0.0;  // m
  int drow = 0;           // grid offset from the label to this neighbour
  int dcol = 0;
};

class ShapeTable {
 public:
  ShapeTable() = default;
  ShapeTable(const ShapeMatrix& shape, double spacing);

  int size() const { return static_cast<int>(rows_.size()); }  // n labels
  double spacing() const { return spacing_; }
  const ShapeMatrix& shape() const { return shape_; }
  // Table II's row of `label` (empty for a label out of range).
  const std::vector<ShapeNeighbour>& neighbours(int label) const;
  bool are_neighbours(int a, int b) const;
  // Position of `label` relative to label 0, shape frame, m.
  Vec2 offset(int label) const;
  // Arena position of `label` when label 0 stands at `origin` and the shape's up points along
  // `shape_heading`.
  Vec2 place(int label, Vec2 origin, double shape_heading) const;
  std::vector<Vec2> places(Vec2 origin, double shape_heading) const;

 private:
  ShapeMatrix shape_;
  double spacing_ = 1.0;
  std::vector<std::vector<ShapeNeighbour>> rows_;  // by label
  std::vector<Vec2> offsets_;                      // by label
};

}  // namespace swarmform::controller
