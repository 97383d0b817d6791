#include "common/id_ranges.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace swarmform {
namespace {

TEST(IdRanges, FewIdsStayApartAndRunsOfThreeOrMoreBecomeRanges) {
  EXPECT_EQ(id_ranges_text({}), "");
  EXPECT_EQ(id_ranges_text({7}), "7");
  EXPECT_EQ(id_ranges_text({3, 7, 12}), "3 7 12");
  EXPECT_EQ(id_ranges_text({1, 2}), "1 2");
  EXPECT_EQ(id_ranges_text({1, 2, 3}), "1-3");
  EXPECT_EQ(id_ranges_text({0, 1, 2, 3, 5, 6, 9, 10, 11, 12, 40}), "0-3 5 6 9-12 40");
}

TEST(IdRanges, AWholeLargeRunIsOneRange) {
  std::vector<RobotId> all;
  for (RobotId id = 0; id < 1024; ++id) all.push_back(id);
  EXPECT_EQ(id_ranges_text(all), "0-1023");
  all.erase(all.begin() + 500);
  EXPECT_EQ(id_ranges_text(all), "0-499 501-1023");
}

TEST(IdRanges, TheLargestIdsDoNotWrapAround) {
  const RobotId top = UINT32_MAX;
  EXPECT_EQ(id_ranges_text({0, top - 2, top - 1, top}),
            "0 " + std::to_string(top - 2) + "-" + std::to_string(top));
  EXPECT_EQ(id_ranges_text({top, 0, 1}), std::to_string(top) + " 0 1");
}

}  // namespace
}  // namespace swarmform
