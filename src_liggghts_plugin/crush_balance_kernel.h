// SPDX-License-Identifier: GPL-2.0-or-later
/* Cut placement of command balance/grains (static load balancing): pure
   functions of a histogram of the grains along one dimension of the box;
   no LIGGGHTS dependency; unit-tested in tests/unit/test_balance_kernel.cpp.

   Conventions
   - Positions are fractions of the box length along the dimension, in
     [0, 1], as LIGGGHTS keeps its cuts (comm->xsplit/ysplit/zsplit).
   - A histogram has nbins equal bins over [0, 1]; counts[j] >= 0 is the
     number of grains (or their summed weight) in bin j.
   - splits has parts + 1 entries: splits[0] = 0, splits[parts] = 1, and the
     rank at grid index k owns [splits[k], splits[k+1]).

   LIGGGHTS cuts the box as a tensor product (one set of cuts per
   dimension), so balancing is per dimension: the cuts of one dimension are
   the quantiles of the grains' distribution along it. */

#ifndef CRUSH_BALANCE_KERNEL_H
#define CRUSH_BALANCE_KERNEL_H

#include <algorithm>
#include <cmath>
#include <vector>

namespace CrushKernels {

// Bin of fractional position f (clamped, so that grains on or just outside
// the box faces count in the end bins).
inline int balance_bin(double f, int nbins)
{
  if (!(f > 0.0)) return 0;  // also NaN
  const int j = static_cast<int>(f * nbins);
  return j >= nbins ? nbins - 1 : j;
}

// Grid index that owns fractional position f (same rule as LIGGGHTS'
// Irregular::coord2proc: splits[k] <= f < splits[k+1], clamped to the ends).
inline int balance_part(double f, const std::vector<double> &splits)
{
  const int parts = static_cast<int>(splits.size()) - 1;
  const int k = static_cast<int>(std::upper_bound(splits.begin(), splits.end(), f) - splits.begin()) - 1;
  if (k < 0) return 0;
  return k >= parts ? parts - 1 : k;
}

// Position where the cumulative count, linear within each bin, reaches
// target (0 < target < total). Where it reaches target on a flat stretch
// (empty bins between grains), the middle of the stretch: the cut then lies
// as far as possible from the grains on either side.
inline double balance_quantile(const std::vector<double> &counts, double target)
{
  const int n = static_cast<int>(counts.size());
  double below = 0.0;  // cumulative count at the left edge of bin j
  for (int j = 0; j < n; j++) {
    const double c = counts[j];
    if (below + c > target) {
      if (target > below) return (j + (target - below) / c) / n;
      // target == below: a flat stretch ends at the left edge of bin j;
      // find where it begins (the right edge of the last non-empty bin)
      int k = j - 1;
      while (k >= 0 && !(counts[k] > 0.0)) k--;
      return 0.5 * ((k + 1) + j) / n;
    }
    below += c;
  }
  return 1.0;
}

// Cuts that give each of `parts` slabs the same share of the counts. Each
// slab is at least min_width wide (fraction of the box; must be < 1/parts),
// so that no rank gets an empty sub-domain where grains are packed in one
// bin. With no grains at all the cuts are uniform.
inline std::vector<double> balance_cuts(const std::vector<double> &counts, int parts, double min_width)
{
  std::vector<double> s(parts + 1);
  double total = 0.0;
  for (size_t j = 0; j < counts.size(); j++) total += counts[j];
  for (int k = 0; k <= parts; k++) s[k] = static_cast<double>(k) / parts;
  if (!(total > 0.0) || parts < 2) return s;
  for (int k = 1; k < parts; k++) s[k] = balance_quantile(counts, total * k / parts);
  // minimum width, forward then backward; the backward sweep cannot undo
  // the forward one because min_width * parts < 1
  for (int k = 1; k < parts; k++) s[k] = std::max(s[k], s[k - 1] + min_width);
  for (int k = parts - 1; k >= 1; k--) s[k] = std::min(s[k], s[k + 1] - min_width);
  return s;
}

// One step of moving the cuts from `current` toward `target`: each cut
// moves at most to the old position of its neighbour cuts. Then every point
// changes owner by at most one grid index, which is what LIGGGHTS' mesh
// element exchange (to the neighbour ranks only) can move. Repeating the
// step reaches target in at most parts - 1 steps; the cuts stay strictly
// increasing when both inputs are.
inline std::vector<double> balance_step(const std::vector<double> &current, const std::vector<double> &target)
{
  const int parts = static_cast<int>(current.size()) - 1;
  std::vector<double> next(current);
  for (int k = 1; k < parts; k++)
    next[k] = std::min(std::max(target[k], current[k - 1]), current[k + 1]);
  return next;
}

// Imbalance of per-rank counts: max / mean (1 = perfect); 1 when all are 0.
inline double balance_imbalance(const std::vector<double> &per_rank)
{
  if (per_rank.empty()) return 1.0;
  double sum = 0.0, mx = 0.0;
  for (size_t i = 0; i < per_rank.size(); i++) {
    sum += per_rank[i];
    mx = std::max(mx, per_rank[i]);
  }
  if (!(sum > 0.0)) return 1.0;
  return mx / (sum / per_rank.size());
}

}  // namespace CrushKernels

#endif
