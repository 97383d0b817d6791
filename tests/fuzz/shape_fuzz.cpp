// libFuzzer target: the shape parser (common/shape.cpp) on any bytes. A rejection must be an InputError; an
// accepted shape must be what the parser promises (labels 0..n-1 once each, 8-connected to label 0).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/input_error.hpp"
#include "common/shape.hpp"
#include "tests/fuzz/fuzz_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  swarmform::ShapeMatrix shape;
  try {
    shape = swarmform::parse_shape_text(text, "<fuzz>");
  } catch (const swarmform::InputError&) {
    return 0;
  }
  FUZZ_CHECK(shape.rows > 0 && shape.cols > 0);
  FUZZ_CHECK(shape.cells.size() ==
             static_cast<std::size_t>(shape.rows) * static_cast<std::size_t>(shape.cols));
  const int n = shape.label_count();
  FUZZ_CHECK(n > 0);
  std::vector<int> seen(static_cast<std::size_t>(n), 0);
  for (int v : shape.cells) {
    FUZZ_CHECK(v >= -1 && v < n);
    if (v >= 0) ++seen[static_cast<std::size_t>(v)];
  }
  for (int count : seen) FUZZ_CHECK(count == 1);
  const auto [r0, c0] = shape.cell_of(0);
  FUZZ_CHECK(r0 >= 0 && c0 >= 0 && shape.at(r0, c0) == 0);
  return 0;
}
