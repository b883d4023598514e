// Natural order of file names (src/read/natural_sort.h): digit runs compare by value, leading
// zeros and long runs do not overflow, ties are broken deterministically, and the order is a
// strict weak order on tricky names.
#include "read/natural_sort.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace mvox {
namespace {

TEST(NaturalSort, DigitRunsCompareByValue) {
  EXPECT_TRUE(natural_less("slice2", "slice10"));
  EXPECT_FALSE(natural_less("slice10", "slice2"));
  EXPECT_TRUE(natural_less("CThead.9", "CThead.10"));
  EXPECT_TRUE(natural_less("a9b", "a10a"));  // the number decides before the text after it
  EXPECT_TRUE(natural_less("img", "img1"));  // a prefix comes first
  EXPECT_TRUE(natural_less("s1_2", "s1_10"));
  // Names sharing the first digits of a run: the run still compares whole (the comparison skips
  // the common prefix only back to where its run starts).
  EXPECT_TRUE(natural_less("s2", "s19"));
  EXPECT_FALSE(natural_less("s19", "s2"));
  EXPECT_TRUE(natural_less("s12", "s123"));
  EXPECT_TRUE(natural_less("x19", "x1000"));
  EXPECT_FALSE(natural_less("x1000", "x19"));
  EXPECT_TRUE(natural_less("a100b", "a1000"));
  EXPECT_TRUE(natural_less("slice_002", "slice_0019"));
  EXPECT_TRUE(natural_less("v12_9", "v12_10"));
  EXPECT_TRUE(natural_less("12", "123"));

  std::vector<std::string> names = {"slice10", "slice1",  "slice12", "slice3",
                                    "slice2",  "slice11", "slice9",  "slice4"};
  natural_sort(names);
  EXPECT_EQ(names, (std::vector<std::string>{"slice1", "slice2", "slice3", "slice4", "slice9",
                                             "slice10", "slice11", "slice12"}));
}

TEST(NaturalSort, LeadingZerosAndLongRunsDoNotOverflow) {
  EXPECT_TRUE(natural_less("a007", "a10"));
  EXPECT_TRUE(natural_less("a0009", "a10"));
  const std::string forty_nines(40, '9');
  const std::string one_then_forty_zeros = "1" + std::string(40, '0');
  EXPECT_TRUE(natural_less("x" + forty_nines, "x" + one_then_forty_zeros));
  EXPECT_FALSE(natural_less("x" + one_then_forty_zeros, "x" + forty_nines));
  // Many leading zeros do not make a number big.
  EXPECT_TRUE(natural_less("x" + std::string(60, '0') + "5", "x6"));
  // Same length, differing late: compared digit by digit.
  EXPECT_TRUE(natural_less("x" + std::string(30, '7') + "1", "x" + std::string(30, '7') + "2"));
}

TEST(NaturalSort, TiesAreBrokenDeterministically) {
  // "a7", "a07", "a007" are the same number; exactly one order holds between any two.
  const std::vector<std::string> same = {"a7", "a07", "a007"};
  for (const auto& p : same) {
    EXPECT_FALSE(natural_less(p, p));
    for (const auto& q : same) {
      if (p != q) EXPECT_NE(natural_less(p, q), natural_less(q, p)) << p << " " << q;
    }
  }
  std::vector<std::string> forward = {"a7", "a07", "a007", "a8"};
  std::vector<std::string> backward(forward.rbegin(), forward.rend());
  natural_sort(forward);
  natural_sort(backward);
  EXPECT_EQ(forward, backward);
  EXPECT_EQ(forward.back(), "a8");
}

TEST(NaturalSort, IsAStrictWeakOrderOnTrickyNames) {
  // Digits next to characters below and above '0'..'9' in ASCII, prefixes, zeros, high bytes.
  const std::vector<std::string> names = {"",
                                          "a",
                                          "a0",
                                          "a00",
                                          "a1",
                                          "a01",
                                          "a1b",
                                          "a1/",
                                          "a1:",
                                          "a/",
                                          "a:",
                                          "a10",
                                          "a2",
                                          "A2",
                                          "a_2",
                                          "a-2",
                                          "a\xff"
                                          "1",
                                          "1",
                                          "01",
                                          "10",
                                          "9",
                                          "9a",
                                          "a2b3",
                                          "a2b10"};
  for (const auto& a : names) {
    EXPECT_FALSE(natural_less(a, a)) << a;
    for (const auto& b : names) {
      if (a != b) EXPECT_NE(natural_less(a, b), natural_less(b, a)) << a << " | " << b;
      for (const auto& c : names) {
        if (natural_less(a, b) && natural_less(b, c)) {
          EXPECT_TRUE(natural_less(a, c)) << a << " < " << b << " < " << c;
        }
      }
    }
  }
}

}  // namespace
}  // namespace mvox
