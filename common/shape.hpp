// A shape: the paper's integer label matrix (section III.B). -1 is empty, labels 0..n-1 appear exactly once
// and are 8-connected. The text format is documented in shapes/README.md. Row 0 is the top line of the file.
// In the arena, column index grows along +x and row index grows along -y (the matrix is drawn as it looks
// from above), one grid spacing apart.
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

}  // namespace swarmform
