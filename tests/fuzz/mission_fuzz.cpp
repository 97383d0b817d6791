// libFuzzer target: the checks an agent makes on a mission off the wire (common/mission_check.cpp), on a
// mission built from any bytes the way common/dds/mission_endpoints.cpp copies a DDS sample's fields: rows,
// cols, the cells, the numbers, and named parameters. A rejection must be an InputError; an accepted mission
// must keep the promises its controller relies on (no shape or a valid one, finite positive lengths and
// rates).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "common/input_error.hpp"
#include "common/mission_check.hpp"
#include "tests/fuzz/fuzz_check.hpp"

namespace {

// Reads little pieces off the input; zeros once it runs out (as a short sample's missing fields would be).
struct Bytes {
  const std::uint8_t* p;
  std::size_t n;
  template <typename T>
  T take() {
    T v{};
    const std::size_t k = n < sizeof(T) ? n : sizeof(T);
    std::memcpy(&v, p, k);
    p += k;
    n -= k;
    return v;
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Bytes in{data, size};
  swarmform::Mission m;
  m.shape.rows = in.take<std::int8_t>();
  m.shape.cols = in.take<std::int8_t>();
  const std::size_t cells = in.take<std::uint8_t>();
  for (std::size_t k = 0; k < cells; ++k) m.shape.cells.push_back(in.take<std::int8_t>());
  m.grid_spacing = in.take<double>();
  m.goal = swarmform::Vec2{in.take<double>(), in.take<double>()};
  m.goal_radius = in.take<double>();
  m.max_speed = in.take<double>();
  m.tick_rate = in.take<double>();
  m.comm_range = in.take<double>();
  const std::size_t params = in.take<std::uint8_t>() % 8;
  for (std::size_t k = 0; k < params; ++k) {
    const std::size_t len = in.take<std::uint8_t>() % 16;
    std::string name;
    for (std::size_t c = 0; c < len; ++c) name += static_cast<char>(in.take<std::uint8_t>());
    m.params[name] = in.take<double>();
  }
  try {
    swarmform::check_mission(m, "<fuzz>");
  } catch (const swarmform::InputError&) {
    return 0;
  }
  FUZZ_CHECK(std::isfinite(m.grid_spacing) && m.grid_spacing > 0 && std::isfinite(m.tick_rate) &&
             m.tick_rate > 0);
  FUZZ_CHECK(std::isfinite(m.comm_range) && m.comm_range > 0 && std::isfinite(m.max_speed) &&
             m.max_speed > 0);
  // No shape at all (0 x 0, no cells) is a mission for a behaviour that forms none (check_mission).
  if (m.shape.rows == 0 && m.shape.cols == 0) {
    FUZZ_CHECK(m.shape.cells.empty());
    return 0;
  }
  FUZZ_CHECK(m.shape.rows > 0 && m.shape.cols > 0);
  FUZZ_CHECK(m.shape.cells.size() == static_cast<std::size_t>(m.shape.rows * m.shape.cols));
  const int n = m.shape.label_count();
  FUZZ_CHECK(n > 0);
  std::vector<int> seen(static_cast<std::size_t>(n), 0);
  for (const int v : m.shape.cells) {
    FUZZ_CHECK(v >= -1 && v < n);
    if (v >= 0) ++seen[static_cast<std::size_t>(v)];
  }
  for (const int count : seen) FUZZ_CHECK(count == 1);
  return 0;
}
