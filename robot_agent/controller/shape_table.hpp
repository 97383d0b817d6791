// The shape table (paper III.B, Table II): for each label, the labels of its 8 neighbours in the matrix with
// their angle and distance, and each label's place.
//
// Angles are in the shape's own frame: column along +x, row along -y (common/shape.hpp), so the neighbour at
// grid offset (drow, dcol) lies at atan2(-drow, dcol), spacing * hypot(drow, dcol) away. Neighbours are
// listed in the order the 3x3 grid is scanned (row by row, left to right), as Table II lists 1, 2, 3.
// In the arena the shape frame is turned so that its +y ("up", towards row 0) points along shape_heading:
// arena = R(shape_heading - pi/2) * shape frame.
//
// The table is immutable once built, and every robot of a swarm builds the same one: tables built from equal
// shapes and spacings in one process share one copy (an in-process run of 1024 robots on a 1024-label shape
// held 1024 copies of ~300 KB, and each robot's lookups in its own copy were cache misses).
#pragma once

#include <memory>
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

  int size() const { return data_ ? static_cast<int>(data_->rows.size()) : 0; }  // n labels
  double spacing() const { return data_ ? data_->spacing : 1.0; }
  const ShapeMatrix& shape() const;
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
  struct Data {
    ShapeMatrix shape;
    double spacing = 1.0;
    std::vector<std::vector<ShapeNeighbour>> rows;  // by label
    std::vector<Vec2> offsets;                      // by label
  };
  static std::shared_ptr<const Data> build(const ShapeMatrix& shape, double spacing);
  std::shared_ptr<const Data> data_;  // shared by the equal tables of the process
};

}  // namespace swarmform::controller
