// Robot ids for a message: "0-1023" rather than 1024 numbers when every agent of a large run is missing, and
// still "3 7 12" for a few. Runs of three or more consecutive ids become FIRST-LAST; shorter ones stay apart.
// The ids are printed in the order given (callers pass them sorted).
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "common/types.hpp"

namespace swarmform {

inline std::string id_ranges_text(const std::vector<RobotId>& ids) {
  std::string out;
  const auto put = [&out](const std::string& s) {
    if (!out.empty()) out += ' ';
    out += s;
  };
  for (std::size_t i = 0; i < ids.size();) {
    std::size_t j = i;  // ids[i..j] are consecutive
    while (j + 1 < ids.size() && ids[j] != std::numeric_limits<RobotId>::max() && ids[j + 1] == ids[j] + 1)
      ++j;
    if (j - i >= 2) {
      put(std::to_string(ids[i]) + "-" + std::to_string(ids[j]));
    } else {
      for (std::size_t k = i; k <= j; ++k) put(std::to_string(ids[k]));
    }
    i = j + 1;
  }
  return out;
}

}  // namespace swarmform
