// A shape: the paper's integer label matrix (section III.B). -1 is empty, labels 0..n-1 appear exactly once
// and are 8-connected. The text format is documented in shapes/README.md. Row 0 is the top line of the file.
// In the shape's own frame, column index grows along +x and row index grows along -y (the matrix is drawn as
// it looks from above), one grid spacing apart: the neighbour at grid offset (drow, dcol) is at angle
// atan2(-drow, dcol). This reproduces the paper's Table II for the triangle's label 0 (labels 1 and 3 at
// -3pi/4 and -pi/4, distances 1.4, 1.0, 1.4) except the sign of label 2's angle, which no grid orientation
// can reproduce together with the other two (shapes/README.md). In the arena the shape's "up" (towards row 0)
// points along the controller parameter shape_heading (default pi/2: shape frame = arena frame).
#pragma once

#include <string>
#include <vector>

namespace swarmform {

struct ShapeMatrix {
  int rows = 0;
  int cols = 0;
  std::vector<int> cells;  // row-major, rows*cols entries, -1 empty

  int at(int row, int col) const { return cells[static_cast<std::size_t>(row * cols + col)]; }
  int label_count() const;  // n
  // Grid cell of a label: {row, col}; {-1,-1} if absent.
  std::pair<int, int> cell_of(int label) const;
};

// Parses and checks a shape; throws InputError naming file:line on anything wrong.
// `origin` is the name used in error messages (a path, or e.g. "<mission>").
ShapeMatrix parse_shape_text(const std::string& text, const std::string& origin);
ShapeMatrix load_shape_file(const std::string& path);
// The checks parse_shape_text makes (labels 0..n-1 once each, one 8-connected piece), on a matrix that came
// from elsewhere, e.g. a mission off the wire: InputError at `origin`, line = the row + 1.
void check_shape(const ShapeMatrix& shape, const std::string& origin);

}  // namespace swarmform
