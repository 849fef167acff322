#include <gtest/gtest.h>
#include "sim/springs.h"
TEST(Springs, Placeholder) { wobble::Springs s; EXPECT_EQ(s.size(), 0u); }
