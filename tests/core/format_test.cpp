// Human-readable numbers in messages (issue 15): the examples the issue gives
// and the edges where rounding carries into the next unit.
#include <gtest/gtest.h>
#include "core/format.h"

namespace lb {
namespace {

TEST(Format, SecondsAsPeopleReadThem) {
  EXPECT_EQ(formatSeconds(4.3e-07), "0 s");
  EXPECT_EQ(formatSeconds(0.0123), "12 ms");
  EXPECT_EQ(formatSeconds(3.456), "3.46 s");
  EXPECT_EQ(formatSeconds(42.14), "42.1 s");
  EXPECT_EQ(formatSeconds(125), "2m05s");
  EXPECT_EQ(formatSeconds(3725), "62m05s");
  EXPECT_EQ(formatSeconds(7260), "2h01m");
  EXPECT_EQ(formatSeconds(0.9996), "1.00 s");  // not "1000 ms"
  EXPECT_EQ(formatSeconds(9.996), "10.0 s");
  EXPECT_EQ(formatSeconds(1e12), "277777777h46m");  // past an int's range
  EXPECT_EQ(formatSeconds(1e300), "forever");
}

TEST(Format, CountsWithSiPrefixesAndThreeDigits) {
  EXPECT_EQ(formatCount(1.12742e+06, "lookups/s"), "1.13 M lookups/s");
  EXPECT_EQ(formatCount(950), "950");
  EXPECT_EQ(formatCount(12345), "12.3 k");
  EXPECT_EQ(formatCount(999.7e3, "rays/s"), "1.00 M rays/s");  // not "1000 k"
  EXPECT_EQ(formatCount(4.56e9), "4.56 G");
  EXPECT_EQ(formatCount(0.5, "x"), "0.50 x");
  EXPECT_EQ(formatCount(12, "spp"), "12 spp");
}

TEST(Format, Bytes) {
  EXPECT_EQ(formatBytes(512), "512 B");
  EXPECT_EQ(formatBytes(22.7747 * (1 << 20)), "22.8 MiB");
}

}  // namespace
}  // namespace lb
