// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix crush/particle: the keywords of the fix command (parse_args, called
   by the constructor). Every keyword, its check and its default are here;
   the syntax is in docs/fix_crush_particle.md "Syntax". The word-level
   checks are those of crush_args.h.
   Exercised by tests/integration/test_crush_errors.py and
   test_bad_input.py (every wrong input) and by every crush deck.
------------------------------------------------------------------------- */

#include "fix_crush_particle.h"

#include <cstring>
#include <string>

#include "crush_args.h"
#include "crush_breakage_index_kernel.h"
#include "crush_criterion_kernel.h"
#include "crush_strength_kernel.h"
#include "error.h"

using namespace LAMMPS_NS;
using namespace FixConst;
using namespace CrushKernels;

/* ---------------------------------------------------------------------- */

void FixCrushParticle::parse_args(int narg, char **arg)
{
  // fix ID group crush/particle sigma_lim0 S m M d0 D scale N var V d_comm DC seed P [...]
  CrushArgs a(error, "fix crush/particle", narg, arg, 3,
              {"sigma_lim0", "m", "d0", "scale", "var", "d_comm", "seed", "br", "d_max", "d_min",
               "omega", "fines_grading", "d_frag_min", "events", "events_append", "dt_check",
               "dt_frac", "dt_omega", "margin_skip", "density_scale", "energy", "energy_window",
               "energy_budget", "pressure", "force", "size_law", "scatter", "f_min"});
  while (a.next()) {
    if (a.is("sigma_lim0")) sigma_lim0_ = a.number(arg_positive("Pa"));
    else if (a.is("m")) m_ = a.number(arg_positive(""));
    else if (a.is("d0")) d0_ = a.number(arg_positive("m"));
    else if (a.is("scale")) scale_N_ = a.number(arg_positive(""));
    else if (a.is("var")) var_ = a.number(arg_non_negative(""));
    else if (a.is("d_comm")) d_comm_ = a.number(arg_positive("m"));
    else if (a.is("seed")) seed_ = (uint64_t)a.prime_seed();
    else if (a.is("br")) {}  // br d_max DMAX d_min DMIN omega W: a heading only
    else if (a.is("d_max")) d_max_ = a.number(arg_positive("m"));
    else if (a.is("d_min")) d_min_ = a.number(arg_positive("m"));
    else if (a.is("omega")) omega_ = a.number(arg_range(0.0, false, 3.0, true, "in (0, 3]"));
    else if (a.is("fines_grading")) fines_fractal_ = a.choice({"fractal", "d_min"}) == 0;
    else if (a.is("d_frag_min")) d_frag_min_ = a.number(arg_non_negative("m"));
    else if (a.is("events")) {
      const std::string f = a.word("a file name");
      delete[] events_file_;
      events_file_ = new char[f.size() + 1];
      strcpy(events_file_, f.c_str());
    }
    else if (a.is("events_append")) events_append_ = a.yes_no();
    else if (a.is("dt_check")) dt_check_error_ = a.choice({"warn", "error"}) == 1;
    else if (a.is("dt_frac")) dt_frac_ = a.number(arg_range(0.0, false, 1.0, true, "in (0, 1]"));
    else if (a.is("dt_omega")) dt_omega_ = a.number(arg_range(0.0, false, 2.0, false, "in (0, 2)"));
    else if (a.is("margin_skip")) margin_skip_ = a.yes_no();
    else if (a.is("density_scale")) d_scale_ref_ = a.number(arg_non_negative("m"));  // 0: off
    else if (a.is("energy")) energy_on_ = a.yes_no();
    else if (a.is("energy_budget")) energy_budget_ = a.yes_no();
    else if (a.is("energy_window")) energy_window_ = (int)a.integer(1, 1000000000, "an integer >= 1 (steps)");
    // criterion readings (docs/fix_crush_particle.md "Criterion readings")
    else if (a.is("pressure")) pressure_ = a.choice({"mean", "peak"}) == 1 ? PRESSURE_PEAK : PRESSURE_MEAN;
    else if (a.is("force")) force_ = a.choice({"normal", "sliding"}) == 1 ? FORCE_SLIDING : FORCE_NORMAL;
    else if (a.is("size_law")) size_law_ = a.choice({"printed", "no_N"}) == 1 ? SIZE_NO_N : SIZE_PRINTED;
    else if (a.is("scatter")) scatter_ = a.choice({"normal", "truncated", "weibull"});
    else if (a.is("f_min")) f_min_ = a.number(arg_range(0.0, true, 1.0, false, "in [0, 1)"));
  }

  if (a.given("f_min") && scatter_ != SCATTER_TRUNCATED)
    error->all(FLERR, "fix crush/particle: keyword 'f_min' belongs to 'scatter truncated'");
  if (scatter_ == SCATTER_TRUNCATED && !a.given("f_min"))
    error->all(FLERR, "fix crush/particle: 'scatter truncated' needs keyword 'f_min' (the bound of f, in [0, 1))");
  if (scatter_ == SCATTER_WEIBULL) {
    if (var_ > 0.0 && !(var_ >= 0.01 && var_ <= 5.0))
      error->all(FLERR, "fix crush/particle: 'scatter weibull' needs keyword 'var' in [0.01, 5] "
                        "(the coefficient of variation of the law), or 0");
    if (var_ > 0.0) weibull_k_ = weibull_shape_for_cov(var_);
  }

  if (energy_budget_ && !energy_on_)
    error->all(FLERR, "fix crush/particle: keyword 'energy_budget yes' needs 'energy yes'");

  static const char *required[] = {"sigma_lim0", "m", "d0", "scale", "var", "d_comm", "seed"};
  for (unsigned k = 0; k < sizeof(required) / sizeof(required[0]); k++)
    if (!a.given(required[k]))
      a.fail("missing required keyword '" + arg_text(required[k]) +
             "' (required: sigma_lim0 m d0 scale var d_comm seed)");

  // Einav limit grading: default NE34 sizes (docs/model.md §3) scaled by N
  if (!a.given("d_max")) d_max_ = 0.27e-3 * scale_N_;
  if (!a.given("d_min")) d_min_ = 0.01e-3 * scale_N_;
  if (!(d_max_ > d_min_))
    error->all(FLERR, "fix crush/particle: keyword 'd_max' must be larger than 'd_min'");

  J0_.assign(kBrBins, 0.0);
  J_fines_.assign(kBrBins, 0.0);
  U_.assign(kBrBins, 0.0);
  br_limit_bins(omega_, br_grid(d_min_, d_max_), &U_[0]);
}
