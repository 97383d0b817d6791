// The shape matrix parser and checker (format: shapes/README.md). Every rejection names file:line.
#include "common/shape.hpp"

#include <algorithm>
#include <charconv>
#include <fstream>
#include <limits>
#include <sstream>
#include <string_view>
#include <utility>

#include "common/input_error.hpp"

namespace swarmform {

namespace {

// A guard against absurd files: no shape of ours needs more, and the checks below are O(cells).
constexpr int kMaxDimension = 1000;

struct ParsedRow {
  int line = 0;  // 1-based line of the file the row came from
  std::vector<int> values;
};

std::string_view strip_comment(std::string_view line) {
  auto hash = line.find('#');
  return hash == std::string_view::npos ? line : line.substr(0, hash);
}

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

std::vector<std::string_view> split_tokens(std::string_view text) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && is_space(text[i])) ++i;
    std::size_t start = i;
    while (i < text.size() && !is_space(text[i])) ++i;
    if (i > start) tokens.push_back(text.substr(start, i - start));
  }
  return tokens;
}

std::vector<ParsedRow> read_rows(const std::string& text, const std::string& origin) {
  std::vector<ParsedRow> rows;
  std::size_t pos = 0;
  int line_no = 0;
  while (pos <= text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    ++line_no;
    auto tokens = split_tokens(strip_comment(std::string_view(text).substr(pos, end - pos)));
    if (!tokens.empty()) {
      ParsedRow row;
      row.line = line_no;
      for (auto token : tokens) {
        int value = 0;
        auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
        if (ec != std::errc() || ptr != token.data() + token.size()) {
          throw InputError(origin, line_no, "not an integer: '" + std::string(token) + "'");
        }
        if (value < -1) {
          throw InputError(origin, line_no,
                           "invalid value " + std::to_string(value) + " (labels are >= 0, -1 is empty)");
        }
        row.values.push_back(value);
      }
      if (!rows.empty() && row.values.size() != rows.front().values.size()) {
        throw InputError(origin, line_no,
                         "ragged row: " + std::to_string(row.values.size()) + " values, but line " +
                             std::to_string(rows.front().line) + " has " +
                             std::to_string(rows.front().values.size()));
      }
      if (static_cast<int>(row.values.size()) > kMaxDimension) {
        throw InputError(origin, line_no, "row longer than " + std::to_string(kMaxDimension) + " values");
      }
      rows.push_back(std::move(row));
      if (static_cast<int>(rows.size()) > kMaxDimension) {
        throw InputError(origin, line_no, "more than " + std::to_string(kMaxDimension) + " rows");
      }
    }
    if (end == text.size()) break;
    pos = end + 1;
  }
  return rows;
}

// Labels must be exactly 0..n-1, each once. Reports the offending label's own line.
void check_labels(const ShapeMatrix& shape, const std::vector<int>& row_line, const std::string& origin) {
  const int cells = shape.rows * shape.cols;
  std::vector<int> first_line(static_cast<std::size_t>(cells), 0);  // indexed by label (< cells when valid)
  int n = 0;
  for (int r = 0; r < shape.rows; ++r) {
    for (int c = 0; c < shape.cols; ++c) {
      if (shape.at(r, c) >= 0) ++n;
    }
  }
  if (n == 0) {
    throw InputError(origin, row_line.empty() ? 1 : row_line.front(),
                     "empty shape: no labels (all cells -1)");
  }
  for (int r = 0; r < shape.rows; ++r) {
    for (int c = 0; c < shape.cols; ++c) {
      const int label = shape.at(r, c);
      if (label < 0) continue;
      const int line = row_line[static_cast<std::size_t>(r)];
      if (label >= n) {
        throw InputError(origin, line,
                         "label " + std::to_string(label) + " out of range: the shape has " +
                             std::to_string(n) + " labels, which must be numbered 0.." +
                             std::to_string(n - 1));
      }
      auto& seen = first_line[static_cast<std::size_t>(label)];
      if (seen != 0) {
        throw InputError(
            origin, line,
            "label " + std::to_string(label) + " appears twice (also on line " + std::to_string(seen) + ")");
      }
      seen = line;
    }
  }
}

// Every label reachable from label 0 through the 8-neighbourhood (paper III.B's 3x3 grid).
void check_connected(const ShapeMatrix& shape, const std::vector<int>& row_line, const std::string& origin) {
  const int n = shape.label_count();
  std::vector<char> reached(static_cast<std::size_t>(n), 0);
  std::vector<std::pair<int, int>> frontier{shape.cell_of(0)};
  reached[0] = 1;
  while (!frontier.empty()) {
    auto [r, c] = frontier.back();
    frontier.pop_back();
    for (int dr = -1; dr <= 1; ++dr) {
      for (int dc = -1; dc <= 1; ++dc) {
        const int rr = r + dr, cc = c + dc;
        if ((dr == 0 && dc == 0) || rr < 0 || cc < 0 || rr >= shape.rows || cc >= shape.cols) continue;
        const int label = shape.at(rr, cc);
        if (label < 0 || reached[static_cast<std::size_t>(label)]) continue;
        reached[static_cast<std::size_t>(label)] = 1;
        frontier.emplace_back(rr, cc);
      }
    }
  }
  for (int r = 0; r < shape.rows; ++r) {
    for (int c = 0; c < shape.cols; ++c) {
      const int label = shape.at(r, c);
      if (label >= 0 && !reached[static_cast<std::size_t>(label)]) {
        throw InputError(origin, row_line[static_cast<std::size_t>(r)],
                         "label " + std::to_string(label) +
                             " is not 8-connected to label 0 (the shape must be one piece)");
      }
    }
  }
}

}  // namespace

int ShapeMatrix::label_count() const {
  return static_cast<int>(std::count_if(cells.begin(), cells.end(), [](int v) { return v >= 0; }));
}

std::pair<int, int> ShapeMatrix::cell_of(int label) const {
  if (label < 0) return {-1, -1};
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      if (at(r, c) == label) return {r, c};
    }
  }
  return {-1, -1};
}

ShapeMatrix parse_shape_text(const std::string& text, const std::string& origin) {
  const auto rows = read_rows(text, origin);
  if (rows.empty()) throw InputError(origin, 1, "empty shape: no rows (only blank lines or comments)");
  ShapeMatrix shape;
  shape.rows = static_cast<int>(rows.size());
  shape.cols = static_cast<int>(rows.front().values.size());
  std::vector<int> row_line;
  for (const auto& row : rows) {
    shape.cells.insert(shape.cells.end(), row.values.begin(), row.values.end());
    row_line.push_back(row.line);
  }
  check_labels(shape, row_line, origin);
  check_connected(shape, row_line, origin);
  return shape;
}

void check_shape(const ShapeMatrix& shape, const std::string& origin) {
  if (shape.rows <= 0 || shape.cols <= 0 ||
      static_cast<std::size_t>(shape.rows) * static_cast<std::size_t>(shape.cols) != shape.cells.size()) {
    throw InputError(origin, 0,
                     "shape of " + std::to_string(shape.rows) + "x" + std::to_string(shape.cols) + " with " +
                         std::to_string(shape.cells.size()) + " cells");
  }
  std::vector<int> row_line(static_cast<std::size_t>(shape.rows));
  for (int r = 0; r < shape.rows; ++r) row_line[static_cast<std::size_t>(r)] = r + 1;
  check_labels(shape, row_line, origin);
  check_connected(shape, row_line, origin);
}

ShapeMatrix load_shape_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "cannot open the shape file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(path, 0, "cannot read the shape file");
  return parse_shape_text(text.str(), path);
}

}  // namespace swarmform
