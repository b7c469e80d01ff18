// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   The plugin's shared keyword parser; see crush_args.h.
------------------------------------------------------------------------- */

#include "crush_args.h"

#include "error.h"

using namespace LAMMPS_NS;
using namespace CrushKernels;

CrushArgs::CrushArgs(Error *error, const std::string &style, int narg, char **arg, int first,
                     const std::vector<std::string> &keywords) :
  error_(error), style_(style), narg_(narg), arg_(arg), iarg_(first), keys_(keywords)
{
}

void CrushArgs::fail(const std::string &msg) const
{
  error_->all(FLERR, (style_ + ": " + msg).c_str());
}

bool CrushArgs::next()
{
  if (iarg_ >= narg_) {
    key_.clear();
    return false;
  }
  key_ = arg_[iarg_++];
  const std::string msg = keys_.take(key_);
  if (!msg.empty()) fail(msg);
  return true;
}

bool CrushArgs::has_value() const
{
  return iarg_ < narg_ && !keys_.known(arg_[iarg_]);
}

const char *CrushArgs::value(const std::string &needs)
{
  if (iarg_ >= narg_) fail(arg_missing_value_message(key_, needs));
  return arg_[iarg_++];
}

double CrushArgs::number_of(const char *text, const ArgRange &range, const std::string &what)
{
  double v = 0.0;
  const std::string msg = arg_check_number(key_, text, range, what, &v);
  if (!msg.empty()) fail(msg);
  return v;
}

double CrushArgs::number(const ArgRange &range, const std::string &what)
{
  // "a number > 0 (Pa)", but "a finite z (m)" as it stands
  const std::string &t = range.text;
  const bool phrase = t.compare(0, 2, "a ") == 0 || t.compare(0, 3, "an ") == 0 ||
                      t.compare(0, 4, "any ") == 0;
  return number_of(value(phrase ? t : "a number " + t), range, what);
}

long CrushArgs::integer(long lo, long hi, const std::string &allowed)
{
  long v = 0;
  const std::string msg = arg_check_integer(key_, value(allowed), lo, hi, allowed, &v);
  if (!msg.empty()) fail(msg);
  return v;
}

long CrushArgs::prime_seed()
{
  long v = 0;
  const std::string msg = arg_check_prime_seed(key_, value("a prime number > 10000"), &v);
  if (!msg.empty()) fail(msg);
  return v;
}

int CrushArgs::choice(const std::vector<std::string> &words)
{
  int index = -1;
  const std::string msg = arg_check_choice(key_, value(arg_words_text(words)), words, &index);
  if (!msg.empty()) fail(msg);
  return index;
}

std::string CrushArgs::word(const std::string &needs)
{
  return value(needs);
}
