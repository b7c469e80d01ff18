// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   The keyword parser every style of the plugin uses: walks the keyword /
   value list of a fix or compute command, and stops the run with
   error->all ("fix crush/particle: keyword 'm' must be > 0, got -1") on an
   unknown or repeated keyword, a missing value, a word where a number
   belongs, NaN, inf, an overflowing number (1e999) or a value out of
   range. The checks and message texts are crush_args_kernel.h
   (unit-tested); this class only walks arg[] and calls error->all.

   Use:
     CrushArgs a(error, "fix damp/local", narg, arg, 3, {"alpha"});
     while (a.next())
       if (a.is("alpha")) alpha = a.number(arg_range(0, true, 1, false, "in [0, 1)"));
     if (!a.given("alpha")) a.fail("missing required keyword 'alpha' ...");
------------------------------------------------------------------------- */

#ifndef LMP_CRUSH_ARGS_H
#define LMP_CRUSH_ARGS_H

#include <string>
#include <vector>

#include "crush_args_kernel.h"

namespace LAMMPS_NS {

// A C string of LIGGGHTS (a fix's id, a style, an arg word) for a message;
// null reads as "" so that a message never dereferences it.
inline std::string arg_text(const char *a) { return std::string(a ? a : ""); }

class CrushArgs {
 public:
  // style: the command as messages name it ("fix crush/particle");
  // first: index of the first keyword in arg; keywords: all the style takes
  CrushArgs(class Error *error, const std::string &style, int narg, char **arg, int first,
            const std::vector<std::string> &keywords);

  // Moves to the next keyword (false after the last word). Stops the run on
  // an unknown keyword or one given twice. A keyword's values must be read
  // (number, word, ...) before the next call.
  bool next();
  const std::string &key() const { return key_; }
  bool is(const char *k) const { return key_ == k; }
  bool given(const char *k) const { return keys_.seen(k); }
  // index in arg of the next word not read yet
  int position() const { return iarg_; }

  // The keyword's next value as a real number in `range` (finite); `what`
  // is an optional description for messages, e.g. "push velocity".
  double number(const CrushKernels::ArgRange &range, const std::string &what = "");
  // `text` (a value already read, e.g. with word()) as such a number
  double number_of(const char *text, const CrushKernels::ArgRange &range,
                   const std::string &what = "");
  // an integer in [lo, hi]; `allowed` says so, e.g. "an integer >= 1 (steps)"
  long integer(long lo, long hi, const std::string &allowed);
  // a prime number > 10000 (random seeds)
  long prime_seed();
  // one of `words`; returns its index
  int choice(const std::vector<std::string> &words);
  bool yes_no() { return choice({"yes", "no"}) == 0; }
  // any word (an ID, a file name); `needs` says what it is, for the
  // message when it is missing
  std::string word(const std::string &needs);
  // true when the next word exists and is not one of the keywords (lists
  // of values such as 'leaving 0 2')
  bool has_value() const;

  // Stops the run: "STYLE: msg"
  void fail(const std::string &msg) const;

 private:
  class Error *error_;
  std::string style_;
  int narg_;
  char **arg_;
  int iarg_;
  std::string key_;
  CrushKernels::ArgKeywords keys_;

  // the next word as the keyword's value (stops the run when there is none)
  const char *value(const std::string &needs);
};

}  // namespace LAMMPS_NS

#endif
