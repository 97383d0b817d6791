// The branch-free lower bound of the controller's sorted tables, against std::lower_bound.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "robot_agent/controller/sorted_search.hpp"

namespace swarmform::controller {
namespace {

TEST(SortedSearch, FindsWhatStdLowerBoundFindsForEverySizeAndKey) {
  std::mt19937 rng(7);
  for (std::size_t n = 0; n <= 70; ++n) {
    std::vector<std::uint32_t> values(n);
    for (auto& v : values) v = static_cast<std::uint32_t>(rng() % 50);  // duplicates included
    std::sort(values.begin(), values.end());
    for (std::uint32_t key = 0; key <= 51; ++key) {
      const auto expected =
          static_cast<std::size_t>(std::lower_bound(values.begin(), values.end(), key) - values.begin());
      EXPECT_EQ(lower_bound_index(values.data(), n, key, [](std::uint32_t v) { return v; }), expected)
          << "n " << n << " key " << key;
    }
  }
}

TEST(SortedSearch, SearchesByTheKeyItIsGiven) {
  struct Row {
    int key;
    char payload;
  };
  const std::vector<Row> rows = {{2, 'a'}, {5, 'b'}, {9, 'c'}};
  const auto key_of = [](const Row& r) { return r.key; };
  EXPECT_EQ(lower_bound_index(rows.data(), rows.size(), 5, key_of), 1u);
  EXPECT_EQ(lower_bound_index(rows.data(), rows.size(), 6, key_of), 2u);
  EXPECT_EQ(lower_bound_index(rows.data(), rows.size(), 10, key_of), 3u);
  EXPECT_EQ(lower_bound_index(rows.data(), rows.size(), 1, key_of), 0u);
}

}  // namespace
}  // namespace swarmform::controller
