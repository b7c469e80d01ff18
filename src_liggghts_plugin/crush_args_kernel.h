// SPDX-License-Identifier: GPL-2.0-or-later
/* Keyword arguments of the plugin's styles: reading and checking one value
   at a time. Every function returns an empty string when the value is
   good, else the error message (without the style's name in front; the
   LIGGGHTS adapter crush_args.h adds it and stops the run). Messages name
   the keyword, the value given and what is allowed, with its unit.
   No LIGGGHTS dependency; unit-tested in tests/unit/test_args_kernel.cpp. */

#ifndef CRUSH_ARGS_KERNEL_H
#define CRUSH_ARGS_KERNEL_H

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

namespace CrushKernels {

// Allowed values of a real keyword: an interval (either end may be open,
// closed or infinite) and how messages describe it, e.g. "> 0 (Pa)",
// "in (0, 3]", "> 0 and <= 360 (degrees)". A value must also be finite.
struct ArgRange {
  double lo, hi;
  bool lo_closed, hi_closed;
  std::string text;

  bool contains(double v) const
  {
    // written so that NaN is outside every range
    const bool above = lo_closed ? (v >= lo) : (v > lo);
    const bool below = hi_closed ? (v <= hi) : (v < hi);
    return above && below && std::isfinite(v);
  }
};

inline ArgRange arg_range(double lo, bool lo_closed, double hi, bool hi_closed,
                          const std::string &text)
{
  ArgRange r;
  r.lo = lo;
  r.hi = hi;
  r.lo_closed = lo_closed;
  r.hi_closed = hi_closed;
  r.text = text;
  return r;
}

// "> 0 (unit)"; unit may be empty (dimensionless)
inline ArgRange arg_positive(const std::string &unit)
{
  return arg_range(0.0, false, std::numeric_limits<double>::infinity(), false,
                   "> 0" + (unit.empty() ? std::string() : " (" + unit + ")"));
}

// ">= 0 (unit)"
inline ArgRange arg_non_negative(const std::string &unit)
{
  return arg_range(0.0, true, std::numeric_limits<double>::infinity(), false,
                   ">= 0" + (unit.empty() ? std::string() : " (" + unit + ")"));
}

// any finite number, described by `text` (e.g. "a finite z (m)")
inline ArgRange arg_any(const std::string &text)
{
  const double inf = std::numeric_limits<double>::infinity();
  return arg_range(-inf, false, inf, false, text);
}

// How a token reads as a real number.
enum ArgNumberStatus {
  ARG_NUMBER_OK,
  ARG_NOT_A_NUMBER,   // empty, a word, trailing characters ("2mm")
  ARG_NOT_FINITE,     // nan, inf, infinity (as strtod reads them)
  ARG_OVERFLOW        // beyond the largest double, e.g. 1e999
};

// The whole token must be a number (strtod syntax). Values that underflow
// (1e-999) read as strtod returns them (0 or subnormal): the range decides.
inline ArgNumberStatus arg_read_number(const char *text, double *value)
{
  *value = 0.0;
  if (!text || !*text) return ARG_NOT_A_NUMBER;
  char *end = nullptr;
  errno = 0;
  const double v = std::strtod(text, &end);
  const bool overflow = (errno == ERANGE && std::isinf(v));
  if (end == text || *end != '\0') return ARG_NOT_A_NUMBER;
  *value = v;
  if (overflow) return ARG_OVERFLOW;
  if (!std::isfinite(v)) return ARG_NOT_FINITE;
  return ARG_NUMBER_OK;
}

// "keyword 'v' (push velocity)" or "keyword 'v'"
inline std::string arg_keyword_text(const std::string &key, const std::string &what)
{
  return "keyword '" + key + "'" + (what.empty() ? std::string() : " (" + what + ")");
}

inline std::string arg_not_a_number_message(const std::string &key, const std::string &text,
                                             const std::string &allowed)
{
  return "value '" + text + "' of keyword '" + key + "' is not a number; allowed: " + allowed;
}

// The value `text` of `key` as a real number in `range`.
inline std::string arg_check_number(const std::string &key, const char *text,
                                    const ArgRange &range, const std::string &what,
                                    double *value)
{
  const std::string t = text ? text : "";
  const ArgNumberStatus s = arg_read_number(t.c_str(), value);
  if (s == ARG_NOT_A_NUMBER) return arg_not_a_number_message(key, t, range.text);
  if (s == ARG_NUMBER_OK && range.contains(*value)) return std::string();
  std::string msg = arg_keyword_text(key, what) + " must be " + range.text + ", got " + t;
  if (s == ARG_NOT_FINITE) msg += " (not a finite number)";
  else if (s == ARG_OVERFLOW) msg += " (beyond the largest double)";
  return msg;
}

// The value `text` of `key` as an integer in [lo, hi] (hi at most
// 2147483647: LIGGGHTS keeps such settings in an int). Exponent notation
// of an integer (2e4, as ${var} may expand) is accepted. `allowed` says it,
// e.g. "an integer >= 1 (steps)".
inline std::string arg_check_integer(const std::string &key, const char *text, long lo, long hi,
                                     const std::string &allowed, long *value)
{
  const std::string t = text ? text : "";
  double v = 0.0;
  const ArgNumberStatus s = arg_read_number(t.c_str(), &v);
  *value = 0;
  if (s == ARG_NOT_A_NUMBER) return arg_not_a_number_message(key, t, allowed);
  if (s != ARG_NUMBER_OK || v != std::floor(v) || v < (double)lo || v > (double)hi)
    return arg_keyword_text(key, "") + " must be " + allowed + ", got " + t;
  *value = (long)v;
  return std::string();
}

inline bool arg_is_prime(long n)
{
  if (n < 2) return false;
  for (long k = 2; k * k <= n; k++)
    if (n % k == 0) return false;
  return true;
}

// A random seed: a prime number above 10000 that fits an int.
inline std::string arg_check_prime_seed(const std::string &key, const char *text, long *value)
{
  const std::string allowed = "a prime number > 10000";
  std::string msg = arg_check_integer(key, text, 10001, 2147483647L, allowed, value);
  if (msg.empty() && !arg_is_prime(*value))
    msg = arg_keyword_text(key, "") + " must be " + allowed + ", got " + (text ? text : "");
  return msg;
}

// "'a' or 'b'", "'a', 'b' or 'c'"
inline std::string arg_words_text(const std::vector<std::string> &words)
{
  std::string s;
  for (size_t i = 0; i < words.size(); i++) {
    if (i > 0) s += (i + 1 == words.size()) ? " or " : ", ";
    s += "'" + words[i] + "'";
  }
  return s;
}

// The value `text` of `key` as one of `words`; *index is its position.
inline std::string arg_check_choice(const std::string &key, const char *text,
                                    const std::vector<std::string> &words, int *index)
{
  const std::string t = text ? text : "";
  for (size_t i = 0; i < words.size(); i++)
    if (t == words[i]) {
      *index = (int)i;
      return std::string();
    }
  *index = -1;
  return arg_keyword_text(key, "") + " must be " + arg_words_text(words) + ", got '" + t + "'";
}

// "keyword 'alpha' needs a value: a number in [0, 1)"
inline std::string arg_missing_value_message(const std::string &key, const std::string &needs)
{
  return "keyword '" + key + "' needs a value" + (needs.empty() ? std::string() : ": " + needs);
}

// The keywords a style takes, and those seen so far on its command line:
// an unknown keyword is named with the list of the known ones, and a
// keyword given twice is an error (a later value would silently win).
class ArgKeywords {
 public:
  explicit ArgKeywords(const std::vector<std::string> &known) : known_(known) {}

  bool known(const std::string &key) const
  {
    for (size_t i = 0; i < known_.size(); i++)
      if (known_[i] == key) return true;
    return false;
  }

  bool seen(const std::string &key) const
  {
    for (size_t i = 0; i < seen_.size(); i++)
      if (seen_[i] == key) return true;
    return false;
  }

  // "a, b, c"
  std::string list() const
  {
    std::string s;
    for (size_t i = 0; i < known_.size(); i++) s += (i ? ", " : "") + known_[i];
    return s;
  }

  // Records `key`; the error message if it is unknown or already given.
  std::string take(const std::string &key)
  {
    if (!known(key)) return "unknown keyword '" + key + "'; expected " + list();
    if (seen(key)) return "keyword '" + key + "' is given twice; give each keyword once";
    seen_.push_back(key);
    return std::string();
  }

 private:
  std::vector<std::string> known_;
  std::vector<std::string> seen_;
};

}  // namespace CrushKernels

#endif
