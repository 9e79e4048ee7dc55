#include "util/excerpt.h"

#include <gtest/gtest.h>

namespace memloop {
namespace {

TEST(ExcerptTest, ShortTextIsWholeLongTextIsItsStartAndLength) {
  EXPECT_EQ(Excerpt("0.11"), "0.11");
  EXPECT_EQ(Excerpt(std::string(60, 'a')), std::string(60, 'a'));
  EXPECT_EQ(Excerpt(std::string(61, 'a')), std::string(40, 'a') + "... (61 characters)");
  EXPECT_EQ(Excerpt(std::string(10000000, '9')),
            std::string(40, '9') + "... (10000000 characters)");
}

}  // namespace
}  // namespace memloop
