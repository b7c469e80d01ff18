// SPDX-License-Identifier: GPL-2.0-or-later
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "crush_args_kernel.h"

using namespace CrushKernels;

namespace {

bool contains(const std::string &s, const std::string &part)
{
  return s.find(part) != std::string::npos;
}

}  // namespace

TEST(ArgsKernel, ReadNumberTellsNumbersWordsNonFiniteAndOverflow)
{
  double v = -1.0;
  EXPECT_EQ(arg_read_number("1.9e9", &v), ARG_NUMBER_OK);
  EXPECT_EQ(v, 1.9e9);
  EXPECT_EQ(arg_read_number("-0.5", &v), ARG_NUMBER_OK);
  EXPECT_EQ(v, -0.5);
  EXPECT_EQ(arg_read_number("0", &v), ARG_NUMBER_OK);
  EXPECT_EQ(v, 0.0);
  for (const char *word : {"", "ten", "2mm", "0.05x", "1e", "--1", " "})
    EXPECT_EQ(arg_read_number(word, &v), ARG_NOT_A_NUMBER) << word;
  EXPECT_EQ(arg_read_number(nullptr, &v), ARG_NOT_A_NUMBER);
  for (const char *nf : {"nan", "NaN", "-nan", "inf", "-inf", "Infinity"})
    EXPECT_EQ(arg_read_number(nf, &v), ARG_NOT_FINITE) << nf;
  for (const char *big : {"1e999", "-1e999", "2e308"})
    EXPECT_EQ(arg_read_number(big, &v), ARG_OVERFLOW) << big;
  // the largest double itself is a number; underflow reads as strtod gives it
  EXPECT_EQ(arg_read_number("1.7976931348623157e308", &v), ARG_NUMBER_OK);
  EXPECT_EQ(arg_read_number("1e-999", &v), ARG_NUMBER_OK);
  EXPECT_EQ(v, 0.0);
}

TEST(ArgsKernel, RangesRejectNaNAndInfinity)
{
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const ArgRange pos = arg_positive("Pa");
  EXPECT_EQ(pos.text, "> 0 (Pa)");
  EXPECT_TRUE(pos.contains(1e-300));
  EXPECT_TRUE(pos.contains(1e300));
  EXPECT_FALSE(pos.contains(0.0));
  EXPECT_FALSE(pos.contains(-1.0));
  EXPECT_FALSE(pos.contains(inf));
  EXPECT_FALSE(pos.contains(nan));
  const ArgRange nn = arg_non_negative("");
  EXPECT_EQ(nn.text, ">= 0");
  EXPECT_TRUE(nn.contains(0.0));
  EXPECT_FALSE(nn.contains(-1e-300));
  const ArgRange half_open = arg_range(0.0, true, 1.0, false, "in [0, 1)");
  EXPECT_TRUE(half_open.contains(0.0));
  EXPECT_TRUE(half_open.contains(0.999));
  EXPECT_FALSE(half_open.contains(1.0));
  const ArgRange omega = arg_range(0.0, false, 3.0, true, "in (0, 3]");
  EXPECT_FALSE(omega.contains(0.0));
  EXPECT_TRUE(omega.contains(3.0));
  EXPECT_FALSE(omega.contains(3.0000001));
  const ArgRange any = arg_any("a finite z (m)");
  EXPECT_TRUE(any.contains(-1e300));
  EXPECT_FALSE(any.contains(-inf));
  EXPECT_FALSE(any.contains(nan));
}

TEST(ArgsKernel, NumberMessagesNameKeywordValueAndRange)
{
  double v = 0.0;
  const ArgRange pos = arg_positive("m/s");
  EXPECT_EQ(arg_check_number("v", "0.5", pos, "push velocity", &v), "");
  EXPECT_EQ(v, 0.5);
  EXPECT_EQ(arg_check_number("v", "0", pos, "push velocity", &v),
            "keyword 'v' (push velocity) must be > 0 (m/s), got 0");
  EXPECT_EQ(arg_check_number("v", "-0.5", pos, "", &v), "keyword 'v' must be > 0 (m/s), got -0.5");
  EXPECT_EQ(arg_check_number("v", "abc", pos, "push velocity", &v),
            "value 'abc' of keyword 'v' is not a number; allowed: > 0 (m/s)");
  EXPECT_EQ(arg_check_number("v", "nan", pos, "", &v),
            "keyword 'v' must be > 0 (m/s), got nan (not a finite number)");
  EXPECT_EQ(arg_check_number("v", "inf", pos, "", &v),
            "keyword 'v' must be > 0 (m/s), got inf (not a finite number)");
  EXPECT_EQ(arg_check_number("v", "1e999", pos, "", &v),
            "keyword 'v' must be > 0 (m/s), got 1e999 (beyond the largest double)");
  // a huge finite value is a number like any other: the range decides
  EXPECT_EQ(arg_check_number("v", "1e300", pos, "", &v), "");
  EXPECT_EQ(v, 1e300);
  // an empty word (a missing value is caught before, by the adapter)
  EXPECT_EQ(arg_check_number("v", "", pos, "", &v),
            "value '' of keyword 'v' is not a number; allowed: > 0 (m/s)");
}

TEST(ArgsKernel, IntegersAcceptExponentNotationAndRejectFractionsAndOverflow)
{
  long n = 0;
  const std::string allowed = "an integer >= 1 (steps)";
  EXPECT_EQ(arg_check_integer("every", "10", 1, 2147483647L, allowed, &n), "");
  EXPECT_EQ(n, 10);
  EXPECT_EQ(arg_check_integer("every", "2e4", 1, 2147483647L, allowed, &n), "");
  EXPECT_EQ(n, 20000);
  EXPECT_EQ(arg_check_integer("every", "2.5", 1, 2147483647L, allowed, &n),
            "keyword 'every' must be an integer >= 1 (steps), got 2.5");
  EXPECT_EQ(arg_check_integer("every", "0", 1, 2147483647L, allowed, &n),
            "keyword 'every' must be an integer >= 1 (steps), got 0");
  for (const char *bad : {"3e9", "1e999", "inf", "nan", "-1"})
    EXPECT_TRUE(contains(arg_check_integer("every", bad, 1, 2147483647L, allowed, &n),
                         "must be an integer >= 1 (steps), got " + std::string(bad)))
        << bad;
  EXPECT_EQ(arg_check_integer("every", "often", 1, 2147483647L, allowed, &n),
            "value 'often' of keyword 'every' is not a number; allowed: an integer >= 1 (steps)");
}

TEST(ArgsKernel, PrimeSeeds)
{
  long s = 0;
  EXPECT_TRUE(arg_is_prime(2));
  EXPECT_TRUE(arg_is_prime(10007));
  EXPECT_TRUE(arg_is_prime(15485863));
  EXPECT_TRUE(arg_is_prime(2147483647L));
  EXPECT_FALSE(arg_is_prime(1));
  EXPECT_FALSE(arg_is_prime(15485864));
  EXPECT_FALSE(arg_is_prime(10001));  // 73 * 137
  EXPECT_EQ(arg_check_prime_seed("seed", "10007", &s), "");  // smallest prime > 10000
  EXPECT_EQ(s, 10007);
  EXPECT_EQ(arg_check_prime_seed("seed", "15485863", &s), "");
  for (const char *bad : {"9973", "15485864", "15485863.5", "1e30", "-15485863", "inf", "nan"})
    EXPECT_EQ(arg_check_prime_seed("seed", bad, &s),
              "keyword 'seed' must be a prime number > 10000, got " + std::string(bad))
        << bad;
  EXPECT_TRUE(contains(arg_check_prime_seed("seed", "lucky", &s), "is not a number"));
}

TEST(ArgsKernel, Choices)
{
  int i = -2;
  const std::vector<std::string> yn = {"yes", "no"};
  EXPECT_EQ(arg_check_choice("contacts", "no", yn, &i), "");
  EXPECT_EQ(i, 1);
  EXPECT_EQ(arg_check_choice("contacts", "maybe", yn, &i),
            "keyword 'contacts' must be 'yes' or 'no', got 'maybe'");
  EXPECT_EQ(i, -1);
  EXPECT_EQ(arg_words_text({"a"}), "'a'");
  EXPECT_EQ(arg_words_text({"a", "b", "c"}), "'a', 'b' or 'c'");
  // case matters, as in LIGGGHTS
  EXPECT_NE(arg_check_choice("contacts", "Yes", yn, &i), "");
}

TEST(ArgsKernel, KeywordsUnknownAndRepeated)
{
  ArgKeywords k({"alpha", "beta"});
  EXPECT_EQ(k.list(), "alpha, beta");
  EXPECT_TRUE(k.known("beta"));
  EXPECT_FALSE(k.known("gamma"));
  EXPECT_EQ(k.take("alpha"), "");
  EXPECT_TRUE(k.seen("alpha"));
  EXPECT_FALSE(k.seen("beta"));
  EXPECT_EQ(k.take("gamma"), "unknown keyword 'gamma'; expected alpha, beta");
  EXPECT_EQ(k.take("alpha"), "keyword 'alpha' is given twice; give each keyword once");
  EXPECT_EQ(k.take("beta"), "");
  EXPECT_EQ(arg_missing_value_message("alpha", "a number in [0, 1)"),
            "keyword 'alpha' needs a value: a number in [0, 1)");
  EXPECT_EQ(arg_missing_value_message("alpha", ""), "keyword 'alpha' needs a value");
}
