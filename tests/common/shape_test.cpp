// The shape parser: the format of shapes/README.md, every rejection with file:line, every shipped shape.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "common/input_error.hpp"
#include "common/shape.hpp"

namespace swarmform {
namespace {

// Runs the parser and returns the InputError's text ("" if it parsed).
std::string error_of(const std::string& text) {
  try {
    parse_shape_text(text, "t.txt");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ShapeParser, ReadsRowsCommentsAndBlankLines) {
  const auto shape = parse_shape_text(
      "# a comment line\n"
      "\n"
      "-1  0 -1   # trailing comment\n"
      "\t1 2 3\r\n"
      "\n",
      "t.txt");
  EXPECT_EQ(shape.rows, 2);
  EXPECT_EQ(shape.cols, 3);
  EXPECT_EQ(shape.label_count(), 4);
  EXPECT_EQ(shape.at(0, 1), 0);
  EXPECT_EQ(shape.at(1, 2), 3);
  EXPECT_EQ(shape.cell_of(0), std::make_pair(0, 1));
  EXPECT_EQ(shape.cell_of(3), std::make_pair(1, 2));
  EXPECT_EQ(shape.cell_of(4), std::make_pair(-1, -1));
  EXPECT_EQ(shape.cell_of(-1), std::make_pair(-1, -1));
}

TEST(ShapeParser, RejectsNonIntegerTokenWithItsLine) {
  EXPECT_EQ(error_of("0 1\n2 x3\n"), "t.txt:2: not an integer: 'x3'");
  EXPECT_EQ(error_of("0 1.5\n"), "t.txt:1: not an integer: '1.5'");
  EXPECT_EQ(error_of("\n\n0 99999999999999\n"), "t.txt:3: not an integer: '99999999999999'");
}

TEST(ShapeParser, RejectsRaggedRows) {
  EXPECT_EQ(error_of("# c\n0 1 2\n\n3 4\n"), "t.txt:4: ragged row: 2 values, but line 2 has 3");
}

TEST(ShapeParser, RejectsValuesBelowMinusOne) {
  EXPECT_EQ(error_of("0 1\n-2 2\n"), "t.txt:2: invalid value -2 (labels are >= 0, -1 is empty)");
}

TEST(ShapeParser, RejectsDuplicateLabels) {
  EXPECT_EQ(error_of("0 1\n1 2\n"), "t.txt:2: label 1 appears twice (also on line 1)");
}

TEST(ShapeParser, RejectsLabelsNotNumberedFromZero) {
  EXPECT_EQ(error_of("0 1\n3 -1\n"),
            "t.txt:2: label 3 out of range: the shape has 3 labels, which must be numbered 0..2");
  EXPECT_EQ(error_of("1 2\n"),
            "t.txt:1: label 2 out of range: the shape has 2 labels, which must be numbered 0..1");
}

TEST(ShapeParser, RejectsShapesNotEightConnected) {
  // Diagonal contact connects; a gap of one empty cell does not.
  EXPECT_NO_THROW(parse_shape_text("0 -1\n-1 1\n", "t.txt"));
  EXPECT_EQ(error_of("0 -1 1\n"),
            "t.txt:1: label 1 is not 8-connected to label 0 (the shape must be one piece)");
  EXPECT_EQ(error_of("0 1 -1\n-1 -1 -1\n-1 -1 2\n"),
            "t.txt:3: label 2 is not 8-connected to label 0 (the shape must be one piece)");
}

TEST(ShapeParser, RejectsEmptyShapes) {
  EXPECT_EQ(error_of(""), "t.txt:1: empty shape: no rows (only blank lines or comments)");
  EXPECT_EQ(error_of("# nothing\n\n"), "t.txt:1: empty shape: no rows (only blank lines or comments)");
  EXPECT_EQ(error_of("\n-1 -1\n-1 -1\n"), "t.txt:2: empty shape: no labels (all cells -1)");
}

TEST(ShapeParser, MissingFileIsAnInputError) {
  try {
    load_shape_file("/nonexistent/shape.txt");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/shape.txt: cannot open the shape file");
    EXPECT_EQ(e.line(), 0);
  }
}

TEST(ShapeParser, ReportsTheFileNameOfALoadedFile) {
  const auto path = std::filesystem::temp_directory_path() / "swarmform_shape_test_bad.txt";
  {
    std::ofstream out(path);
    out << "0 1\n2 2\n";
  }
  try {
    load_shape_file(path.string());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path.string());
    EXPECT_EQ(e.line(), 2);
  }
  std::filesystem::remove(path);
}

TEST(ShippedShapes, EveryFileParsesWithSixToThirtyLabels) {
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(SWARMFORM_SHAPES_DIR)) {
    if (entry.path().extension() != ".txt") continue;
    ++files;
    SCOPED_TRACE(entry.path().string());
    ShapeMatrix shape;
    ASSERT_NO_THROW(shape = load_shape_file(entry.path().string()));
    EXPECT_GE(shape.label_count(), 6);
    EXPECT_LE(shape.label_count(), 30);
  }
  EXPECT_GE(files, 7);  // triangle, square, v, arrow, ring, a letter, line
}

TEST(ShippedShapes, TriangleHasLabelZeroAtTheApexAndOneTwoThreeBelowIt) {
  const auto shape = load_shape_file(std::string(SWARMFORM_SHAPES_DIR) + "/triangle.txt");
  const auto [r0, c0] = shape.cell_of(0);
  EXPECT_EQ(r0, 0);  // top row
  EXPECT_EQ(shape.cell_of(1), std::make_pair(r0 + 1, c0 - 1));
  EXPECT_EQ(shape.cell_of(2), std::make_pair(r0 + 1, c0));
  EXPECT_EQ(shape.cell_of(3), std::make_pair(r0 + 1, c0 + 1));
}

}  // namespace
}  // namespace swarmform
