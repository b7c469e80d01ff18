# SPDX-License-Identifier: GPL-2.0-or-later
"""Where the numbers the README and docs/ quote from runs come from (issue 42
item 6): one entry per quoted number, read by tests/python/test_doc_numbers.py.

An entry names the document, a regular expression that finds the quote in
it (whitespace in the pattern matches any run of whitespace, so line breaks
of the markdown do not matter; the number is the first group), the
committed results file the number comes from and the value in it: a path
into the JSON (`a.b[k=v].c`: the element of list b whose field k is v), or
a function of the parsed file. `scale` turns the file's unit into the
quote's (100 for a fraction quoted in %). The test reads the number back
and compares it with the file's value at the quote's precision (half a unit
of its last digit). A doc rewritten so that the quote is gone fails too:
move the pattern with the number.

To add a number: quote it in the doc, add an entry here, and run
`build/venv/bin/python -m pytest tests/python/test_doc_numbers.py`.
"""

import functools
import json
import math
import re
import statistics
from pathlib import Path

import numpy as np

EVR_TABLE = "bench/error_vs_runtime/results_table.json"
DEMO = "bench/demo/summary.json"


def _pooled_ratio(d):
    """The unbreakable/crushable q_c ratio pooled over the four runs of the
    reference setting (bench/error_vs_runtime/run.py --table): mean and
    relative sample sd of the per-setting ratios."""
    keep = set(d["chamber_spread"]["settings"])
    r = np.array([row["ratio"] for row in d["qc_ratio_unbreakable_over_crushable"]
                  if row["setting"] in keep])
    assert r.size == 4, r
    return float(r.mean()), float(r.std(ddof=1) / r.mean())


def _device_pairs(d, ranks):
    """bench/crush_overhead/results_device.json: the fix's own cost (extra
    "Other" over the stock loop) of every pair of the three invocations."""
    return [x for inv in d["invocations"] for x in inv["summary"][ranks]["fix_share_from_other"]]


def _device_ratio_of_medians(d, ranks):
    stock = [x for inv in d["invocations"] for x in inv["summary"][ranks]["stock_loop_s"]]
    crush = [x for inv in d["invocations"] for x in inv["summary"][ranks]["crush_loop_s"]]
    return statistics.median(crush) / statistics.median(stock)


def F(doc, pattern, holds, what):
    """A statement of a doc (pattern: it must be there) that is true only
    while `holds(repo_path)` is: the test fails when the repository changes
    under it, naming `what` to re-check."""
    return {"doc": doc, "pattern": pattern, "holds": holds, "what": what}


def _reads(path, needle):
    return lambda repo: needle in (repo / path).read_text()


def N(doc, pattern, source, value, scale=1.0):
    return {"doc": doc, "pattern": pattern, "source": source, "value": value, "scale": scale}


CROSS = "chamber_spread.models.crushable_ne34"
RIGID = "chamber_spread.models.unbreakable"
PREP = "bench/prep/results.json"
WALL16 = "bench/icount/results_scaling_wall_16core.json"
XL = "bench/extreme_loading/results.json"
CR = "bench/criterion_readings/results.json"

ENTRIES = [
    # --- energy budget and extreme loading (bench/extreme_loading/results.json):
    # the reference page docs/stability.md quotes the headline numbers, the
    # study docs/studies/stability.md the tables
    N("docs/stability.md", r"closes to \*\*([\d.]+) %\*\* of the platen work at the end", XL,
      "oedometer.budget_residual_rel", -100.0),
    N("docs/stability.md", r"of its final value\) with ([\d,]+) breaks to", XL, "oedometer.breaks"),
    N("docs/stability.md", r"to [\d.]+ % \([\d.]+ %\) with ([\d,]+) breaks, and", XL, "oedometer_big.breaks"),
    N("docs/stability.md", r"\(0\.36 %\) with ([\d,]+) breaks in the", XL, "oedometer_small.breaks"),
    N("docs/stability.md", r"MPa \(216 grains, ([\d,]+) breaks\)", XL, "oedometer.breaks"),
    N("docs/stability.md", r"9 x 9 x 9 version \(729 grains, ([\d,]+) breaks\)", XL, "oedometer_big.breaks"),
    N("docs/stability.md", r"fragments up to (\d+) m/s;", XL, "oedometer.largest_fragment_speed_m_s"),
    N("docs/studies/stability.md", r"closes to \*\*([\d.]+) %\*\* of the platen work at the end", XL,
      "oedometer.budget_residual_rel", -100.0),
    N("docs/studies/stability.md", r"of its final value\) with ([\d,]+) breaks to", XL, "oedometer.breaks"),
    N("docs/studies/stability.md", r"to [\d.]+ % \([\d.]+ %\) with ([\d,]+) breaks, and", XL,
      "oedometer_big.breaks"),
    N("docs/studies/stability.md", r"\(0\.36 %\) with ([\d,]+) breaks in the", XL, "oedometer_small.breaks"),
    N("docs/studies/stability.md",
      r"\| oedometer to 100 MPa \(above\) \| 216 \| [\d,]+ \| 3 \| \d+ \(platen, walls\) \| 0 \| [\d.e-]+ \| (\d+) m/s",
      XL, "oedometer.largest_fragment_speed_m_s"),
    N("docs/studies/stability.md", r"\| the test's scene at 2 ranks [^|]*\| 64 \| (\d+) \|", XL,
      "oedometer_small_np2.breaks"),
    # --- error against run time: the pooled run-to-run spread (results_table.json)
    N("docs/studies/error-vs-runtime.md", r"\| crushable \(4 runs\) \| ([\d.]+), sd [\d.]+ %", EVR_TABLE,
      CROSS + ".mean.qc_steady_MPa"),
    N("docs/studies/error-vs-runtime.md", r"\| crushable \(4 runs\) \| [\d.]+, sd ([\d.]+) %", EVR_TABLE,
      CROSS + ".rel_std.qc_steady_MPa", 100.0),
    N("docs/studies/error-vs-runtime.md", r"\| crushable \(4 runs\) \| [\d.]+, sd [\d.]+ % \| ([\d.]+), sd",
      EVR_TABLE, CROSS + ".mean.Br_band_1_2"),
    N("docs/studies/error-vs-runtime.md",
      r"\| crushable \(4 runs\) \| [\d.]+, sd [\d.]+ % \| [\d.]+, sd ([\d.]+) %", EVR_TABLE,
      CROSS + ".rel_std.Br_band_1_2", 100.0),
    N("docs/studies/error-vs-runtime.md",
      r"\| crushable \(4 runs\) \| [^|]+\| [^|]+\| ([\d,]+), sd [\d.]+ %", EVR_TABLE,
      CROSS + ".mean.sigma_r_2R_kPa"),
    N("docs/studies/error-vs-runtime.md",
      r"\| crushable \(4 runs\) \| [^|]+\| [^|]+\| [\d,]+, sd ([\d.]+) %", EVR_TABLE,
      CROSS + ".rel_std.sigma_r_2R_kPa", 100.0),
    N("docs/studies/error-vs-runtime.md", r"\| unbreakable \(4 runs\) \| ([\d.]+), sd [\d.]+ %", EVR_TABLE,
      RIGID + ".mean.qc_steady_MPa"),
    N("docs/studies/error-vs-runtime.md", r"\| unbreakable \(4 runs\) \| [\d.]+, sd ([\d.]+) %", EVR_TABLE,
      RIGID + ".rel_std.qc_steady_MPa", 100.0),
    N("docs/studies/error-vs-runtime.md",
      r"\| unbreakable \(4 runs\) \| [^|]+\| [^|]+\| ([\d,]+), sd [\d.]+ %", EVR_TABLE,
      RIGID + ".mean.sigma_r_2R_kPa"),
    N("docs/studies/error-vs-runtime.md",
      r"\| unbreakable \(4 runs\) \| [^|]+\| [^|]+\| [\d,]+, sd ([\d.]+) %", EVR_TABLE,
      RIGID + ".rel_std.sigma_r_2R_kPa", 100.0),
    N("docs/studies/error-vs-runtime.md", r"one run's standard deviation is ([\d.]+) and [\d.]+ % in q_c",
      EVR_TABLE, CROSS + ".rel_std.qc_steady_MPa", 100.0),
    N("docs/studies/error-vs-runtime.md", r"one run's standard deviation is [\d.]+ and ([\d.]+) % in q_c",
      EVR_TABLE, RIGID + ".rel_std.qc_steady_MPa", 100.0),
    N("docs/studies/error-vs-runtime.md", r"q_c ratio \*\*([\d.]+), sd [\d.]+ %\*\*", EVR_TABLE,
      lambda d: _pooled_ratio(d)[0]),
    N("docs/studies/error-vs-runtime.md", r"q_c ratio \*\*[\d.]+, sd ([\d.]+) %\*\*", EVR_TABLE,
      lambda d: _pooled_ratio(d)[1], 100.0),
    N("docs/report.md", r"\(two packing seeds, two time steps; ([\d.]+) % of q_c", EVR_TABLE,
      CROSS + ".rel_std.qc_steady_MPa", 100.0),
    N("docs/report.md", r"of q_c for crushable grains, ([\d.]+) % for unbreakable", EVR_TABLE,
      RIGID + ".rel_std.qc_steady_MPa", 100.0),
    # --- preparation study (bench/prep/results.json): the reference page
    # docs/preparation.md keeps the study's main rows, docs/studies/preparation.md all
    N("docs/preparation.md", r"\| \*\*core porosity, prepared\*\* [^|]+\| \*\*([\d.]+)\*\*", PREP,
      "cases[case=demo_2024].porosity_core"),
    N("docs/preparation.md", r"\| \*\*core porosity, prepared\*\* [^|]+\| \*\*[\d.]+\*\*; ([\d.]+)",
      PREP, "cases[case=demo_2024].porosity_core_deck"),
    N("docs/preparation.md",
      r"\| \*\*core porosity, prepared\*\* [^|]+\| [^|]+\| \*\*([\d.]+)\*\*", PREP,
      "cases[case=demo_2025].porosity_core"),
    N("docs/preparation.md",
      r"\| \*\*core porosity, prepared\*\* [^|]+\| [^|]+\| [^|]+\| \*\*([\d.]+)\*\*", PREP,
      "cases[case=paper_R216_q].porosity_core"),
    N("docs/studies/preparation.md", r"\| \*\*core porosity, prepared\*\* [^|]+\| \*\*([\d.]+)\*\*", PREP,
      "cases[case=demo_2024].porosity_core"),
    N("docs/studies/preparation.md", r"\| \*\*core porosity, prepared\*\* [^|]+\| \*\*[\d.]+\*\*; ([\d.]+)",
      PREP, "cases[case=demo_2024].porosity_core_deck"),
    N("docs/studies/preparation.md",
      r"\| \*\*core porosity, prepared\*\* [^|]+\| [^|]+\| \*\*([\d.]+)\*\*", PREP,
      "cases[case=demo_2025].porosity_core"),
    N("docs/studies/preparation.md",
      r"\| \*\*core porosity, prepared\*\* [^|]+\| [^|]+\| [^|]+\| \*\*([\d.]+)\*\*", PREP,
      "cases[case=paper_R216_q].porosity_core"),
    # --- performance
    N("docs/studies/performance.md", r"ring stresses in \*\*([\d.]+) s\*\* \(median of 3",
      "bench/report/results.json", "median.total_s"),
    N("docs/studies/performance.md", r"peak resident memory of \*\*([\d.]+) GB\*\*",
      "bench/report/results.json", "median.peak_rss_MB", 1.0 / 1024.0),
    N("docs/report.md", r"stresses in ([\d.]+) s \(median of 3 runs\)",
      "bench/report/results.json", "median.total_s"),
    N("docs/report.md", r"\(median of 3 runs\) and ([\d.]+) GB", "bench/report/results.json",
      "median.peak_rss_MB", 1.0 / 1024.0),
    N("docs/studies/performance.md", r"\| 1 \| [^|]+\| [^|]+\| [^|]+\| [^|]+\| \*\*([\d.]+)\*\* \(0.962",
      "bench/break_cost/results_callgrind.json",
      "summary_medians.np1.crush_over_stock_same_packings"),
    N("docs/studies/performance.md", r"\| 2 \| [^|]+\| [^|]+\| [^|]+\| [^|]+\| \*\*([\d.]+)\*\* \(0.963",
      "bench/break_cost/results_callgrind.json",
      "summary_medians.np2.crush_over_stock_same_packings"),
    N("docs/studies/performance.md", r"\*\*[\d.]+\*\* \(0.962 before the cuts\) \| \*\*([\d.]+)\*\*",
      "bench/break_cost/results_callgrind.json", "summary_medians.np1.crush_over_stock_mean"),
    N("docs/studies/performance.md", r"\*\*[\d.]+\*\* \(0.963\) \| \*\*([\d.]+)\*\*",
      "bench/break_cost/results_callgrind.json", "summary_medians.np2.crush_over_stock_mean"),
    N("docs/studies/performance.md", r"is \*\*([\d.]+) % of the stock loop time at 1 rank\*\*",
      "bench/crush_overhead/results_device.json",
      lambda d: statistics.median(_device_pairs(d, "1")), 100.0),
    N("docs/studies/performance.md", r"and \*\*([\d.]+) % at 2 ranks\*\*",
      "bench/crush_overhead/results_device.json",
      lambda d: statistics.median(_device_pairs(d, "2")), 100.0),
    N("docs/studies/performance.md", r"ratios of medians are \*\*([\d.]+) at 1 rank",
      "bench/crush_overhead/results_device.json", lambda d: _device_ratio_of_medians(d, "1")),
    N("docs/studies/performance.md", r"ratios of medians are \*\*[\d.]+ at 1 rank and ([\d.]+) at 2 ranks",
      "bench/crush_overhead/results_device.json", lambda d: _device_ratio_of_medians(d, "2")),
    N("docs/studies/performance.md", r"\| 1 \| \| \| 10 \| \*\*([\d.e]+)\*\*", WALL16,
      "summary.rate_1_rank_median"),
    N("docs/studies/performance.md", r"\| 16 \| `\* \* 1` \| no \| 11 \| \*\*([\d.e]+)\*\*", WALL16,
      "summary.rows[np=16,proc_grid=* * 1].rate_median"),
    N("docs/studies/performance.md", r"\| 16 \| `\* \* 1` \| no \| 11 \| [^|]+\| \*\*([\d.]+)\*\*", WALL16,
      "summary.rows[np=16,proc_grid=* * 1].efficiency_vs_1_rank"),
    N("docs/studies/performance.md", r"\| 16 \| `8 1 2` \| yes \| 11 \| \*\*([\d.e]+)\*\*", WALL16,
      "summary.rows[np=16,proc_grid=8 1 2].rate_median"),
    N("docs/studies/performance.md", r"\| 16 \| `8 1 2` \| yes \| 11 \| [^|]+\| \*\*([\d.]+)\*\*", WALL16,
      "summary.rows[np=16,proc_grid=8 1 2].efficiency_vs_1_rank"),
    # the reference page docs/performance.md quotes the study's headline numbers
    N("docs/performance.md", r"is \*\*([\d.]+) % of the stock loop time at 1 rank\*\*",
      "bench/crush_overhead/results_device.json",
      lambda d: statistics.median(_device_pairs(d, "1")), 100.0),
    N("docs/performance.md", r"and \*\*([\d.]+) % at 2 ranks\*\*",
      "bench/crush_overhead/results_device.json",
      lambda d: statistics.median(_device_pairs(d, "2")), 100.0),
    N("docs/performance.md", r"delivers ([\d.]+) of the particle-steps per instruction",
      "bench/break_cost/results_callgrind.json",
      "summary_medians.np1.crush_over_stock_same_packings"),
    N("docs/performance.md", r"and ([\d.]+) against the mean of stock's rates",
      "bench/break_cost/results_callgrind.json", "summary_medians.np1.crush_over_stock_mean"),
    N("docs/performance.md", r"delivers \*\*([\d.e]+)\*\* particle-steps per second at 1 rank",
      WALL16, "summary.rate_1_rank_median"),
    N("docs/performance.md", r"and \*\*([\d.e]+)\*\* at 16 ranks with `balance/grains`", WALL16,
      "summary.rows[np=16,proc_grid=8 1 2].rate_median"),
    N("docs/performance.md", r"an efficiency of \*\*([\d.]+)\*\*", WALL16,
      "summary.rows[np=16,proc_grid=8 1 2].efficiency_vs_1_rank"),
    N("docs/performance.md", r"to ring stresses in \*\*([\d.]+) s\*\* with",
      "bench/report/results.json", "median.total_s"),
    N("docs/performance.md", r"with \*\*([\d.]+) GB\*\* of peak memory",
      "bench/report/results.json", "median.peak_rss_MB", 1.0 / 1024.0),
    N("docs/stability.md", r"\| difference \| [\d,]+ \(([\d.]+) %\) \|",
      "bench/stability_cost/results.json", "relative_cost_difference", 100.0),
    N("docs/stability.md", r"That is (\d+) instructions per grain per step",
      "bench/stability_cost/results.json", "Ir_per_step_per_grain_own"),
    N("docs/studies/stability.md", r"\| difference \| [\d,]+ \(([\d.]+) %\) \|",
      "bench/stability_cost/results.json", "relative_cost_difference", 100.0),
    N("docs/studies/stability.md", r"That is (\d+) instructions per grain per step",
      "bench/stability_cost/results.json", "Ir_per_step_per_grain_own"),
    N("docs/stability.md", r"with its defaults adds \*\*([\d.]+) %\*\* of the",
      "bench/stability_cost/results.json", "relative_cost_difference", 100.0),
]


def _density_rule_row(seed):
    """The row `| present rule | SEED | q_c, b h | breaks (switch-on) | Br |
    sigma_r |` of docs/studies/error-vs-runtime.md ("Density scaling"): the
    criterion-readings chamber pieces of the fragments' velocity rule. Piece
    names hold a dot, so the values are read by function."""
    # each cell: its layout around the number, the number's pattern, the key
    cells = [(r"{}, [\d.]+", r"[\d.]+", "qc_steady_MPa"), (r"{} \(\d+\)", r"\d+", "n_break_events"),
             (r"{}", r"[\d.]+", "Br_band_1_2"), (r"{}", r"[\d,]+", "sigma_r_2R_kPa")]
    out = []
    for i, (_, _, key) in enumerate(cells):
        row = [lay.format("(%s)" % num if j == i else num) for j, (lay, num, _) in enumerate(cells)]
        out.append(N("docs/studies/error-vs-runtime.md",
                     r"\| present rule \| %d \| " % seed + r" \| ".join(row) + r" \|", CR,
                     lambda d, k=key: d["runs"]["chamber_dscale_0.55_seed%d" % seed]["metrics"][k]))
    return out


ENTRIES += _density_rule_row(2024) + _density_rule_row(2025)

# the chamber pieces of the criterion readings (docs/studies/criterion-readings.md, Status)
_CR_DOC = "docs/studies/criterion-readings.md"


def _cr_piece(name, key, scale=1.0):
    return lambda d: d["runs"][name]["metrics"][key] * scale


def _cr_printed(key, scale=1.0):
    return _cr_piece("chamber_printed_seed2024", key, scale)


def _cr_ratio(name):
    return lambda d: _cr_unbreakable_qc() / d["runs"][name]["metrics"]["qc_steady_MPa"]


def _cr_mean(key, *names):
    return lambda d: statistics.mean(d["runs"][n]["metrics"][key] for n in names)


def _cr_mean_qc(*names):
    return _cr_mean("qc_steady_MPa", *names)


def _cr_drop(lower, upper):
    """How much lower (%) the mean q_c of the pieces `lower` is than that of `upper`."""
    return lambda d: 100.0 * (1.0 - _cr_mean_qc(*lower)(d) / _cr_mean_qc(*upper)(d))


@functools.lru_cache(maxsize=None)
def _cr_times(key, name, over):
    """How many times piece `name`'s metric `key` is piece `over`'s."""
    return lambda d: _cr_piece(name, key)(d) / _cr_piece(over, key)(d)


def _cr_unbreakable_qc():
    """The pooled unbreakable reference q_c the study's ratios divide by
    (MPa): the mean over the error-vs-runtime study's two unbreakable
    chamber seeds, as bench/criterion_readings/run.py pools it."""
    path = Path(__file__).resolve().parents[2] / "bench/error_vs_runtime/results.json"
    runs = json.loads(path.read_text())["runs"]
    return statistics.mean(runs[n]["metrics"]["qc_steady_MPa"]
                           for n in ("chamber_rigid_ref", "chamber_rigid_ref_seed2025"))


def _cr_rows(rows, doc=_CR_DOC):
    """Entries for rows (piece, pattern, metric or "ratio", scale) of `doc`."""
    return [N(doc, pattern, CR, _cr_ratio(piece) if key == "ratio" else _cr_piece(piece, key, scale))
            for piece, pattern, key, scale in rows]


_P24 = "chamber_peak_seed2024"  # the peak reading's first seed; _P25 below
ENTRIES += [
    N(_CR_DOC, r"The printed reading, seed 2024: steady q_c ([\d.]+) MPa", CR,
      _cr_printed("qc_steady_MPa")),
    N(_CR_DOC, r"of the 49 during penetration 21 in the zone \(([\d]+) %", CR,
      _cr_printed("fraction_in_zone", 100.0)),
    N(_CR_DOC, r"Br over the penetrated layers ([\d.]+) in 1-2 R", CR,
      _cr_printed("Br_penetrated_1_2R")),
    N(_CR_DOC, r"in 1-2 R and ([\d.]+) in 2-3 R\s+\(more", CR,
      _cr_printed("Br_penetrated_2_3R")),
    N(_CR_DOC, r"([\d]+) break events, 22 of them at switch-on", CR,
      _cr_printed("n_break_events")),
] + _cr_rows((
    # each chamber piece's quoted numbers: (piece, pattern, metric or "ratio", scale)
    ("chamber_peak_truncated_0.5_seed2024", r"Steady q_c ([\d.]+) MPa, a ratio of\s+1.10",
     "qc_steady_MPa", 1.0),
    ("chamber_peak_truncated_0.5_seed2024",
     r"a ratio of\s+([\d.]+) to the unbreakable reference; 7 break", "ratio", 1.0),
    ("chamber_peak_truncated_0.5_seed2024", r"reference; (\d+) break events, every one",
     "n_break_events", 1.0),
    ("chamber_peak_truncated_0.5_seed2024",
     r"penetrated layers Br is ([\d.]+) in 1-2 R and 0.002", "Br_penetrated_1_2R", 1.0),
    ("chamber_peak_truncated_0.5_seed2024", r"0.018 in 1-2 R and ([\d.]+) in 2-3 R\. This",
     "Br_penetrated_2_3R", 1.0),
    (_P24, r"Steady q_c ([\d.]+)\s+MPa, a ratio of 1.43", "qc_steady_MPa", 1.0),
    (_P24, r"a ratio of ([\d.]+) to the unbreakable reference: inside",
     "ratio", 1.0),
    (_P24, r"(\d+) break events: 39 at switch-on", "n_break_events", 1.0),
    (_P24, r"events: (\d+) at switch-on,\s+20 at entry",
     "events_switch_on", 1.0),
    (_P24, r"of the (\d+) during penetration 51", "events_penetration", 1.0),
    (_P24, r"penetration 51 in the zone \((\d+) %\)", "fraction_in_zone",
     100.0),
    (_P24, r"in the zone \(55 %\), (\d+)\s+beyond 5 R",
     "events_beyond_5R_below", 1.0),
    (_P24, r"Br is ([\d.]+) in 1-2 R and 0.068 in 2-3 R, four",
     "Br_penetrated_1_2R", 1.0),
    (_P24, r"0.140 in 1-2 R and ([\d.]+) in 2-3 R, four",
     "Br_penetrated_2_3R", 1.0),
))

# the peak reading's second seed and the Weibull reading's first (the study's
# Status), as rows of the table above, then the peak reading's two seeds together
_P25 = "chamber_peak_seed2025"
_W24 = "chamber_weibull_seed2024"
_T24 = "chamber_truncated_0.5_seed2024"
_R24 = "chamber_printed_seed2024"
_R25 = "chamber_printed_seed2025"
_PRINTEDS = (_R24, _R25)
_B25 = "chamber_peak_truncated_0.5_seed2025"
_BOUNDED = ("chamber_peak_truncated_0.5_seed2024", _B25)
_PEAKS = (_P24, _P25)
ENTRIES += _cr_rows((
    (_P25, r"Steady q_c ([\d.]+) MPa, a ratio of 1.31", "qc_steady_MPa", 1.0),
    (_P25, r"a ratio of ([\d.]+) to the\s+unbreakable reference; 153", "ratio", 1.0),
    (_P25, r"reference; (\d+) break events: 36 at switch-on", "n_break_events", 1.0),
    (_P25, r"153 break events: (\d+) at switch-on, 26", "events_switch_on", 1.0),
    (_P25, r"36 at switch-on, (\d+) at entry, and", "events_entry", 1.0),
    (_P25, r"of the (\d+) during penetration 44", "events_penetration", 1.0),
    (_P25, r"during penetration (\d+) in the zone \(48", "events_in_zone", 1.0),
    (_P25, r"in the zone \((\d+) %\), 19 beyond", "fraction_in_zone", 100.0),
    (_P25, r"\(48 %\), (\d+) beyond 5 R", "events_beyond_5R_below", 1.0),
    (_P25, r"Br is ([\d.]+) in 1-2 R\s+and 0.024", "Br_penetrated_1_2R", 1.0),
    (_P25, r"0.123 in 1-2 R\s+and ([\d.]+) in 2-3 R\. The two", "Br_penetrated_2_3R", 1.0),
    (_W24, r"Steady\s+q_c ([\d.]+) MPa, a ratio of 1.09 to the unbreakable reference; 38",
     "qc_steady_MPa", 1.0),
    (_W24, r"a ratio of ([\d.]+) to the unbreakable reference; 38", "ratio", 1.0),
    (_W24, r"reference; (\d+) break\s+events: 3 at switch-on", "n_break_events", 1.0),
    (_W24, r"38 break\s+events: (\d+) at switch-on, 6", "events_switch_on", 1.0),
    (_W24, r"3 at switch-on, (\d+) at entry, and of the 29", "events_entry", 1.0),
    (_W24, r"of the (\d+) during penetration 18 in\s+the zone \(62", "events_penetration", 1.0),
    (_W24, r"during penetration (\d+) in\s+the zone \(62", "events_in_zone", 1.0),
    (_W24, r"the zone \((\d+) %\), none beyond 5 R", "fraction_in_zone", 100.0),
    (_W24, r"layers Br is ([\d.]+) in 1-2 R and 0.014", "Br_penetrated_1_2R", 1.0),
    (_W24, r"0.037 in 1-2 R and ([\d.]+) in 2-3 R\. The", "Br_penetrated_2_3R", 1.0),
    (_W24, r"`weibull` (\d+) and 46 events and a ratio", "n_break_events", 1.0),
    (_T24, r"Steady\s+q_c ([\d.]+) MPa, a ratio of 0.99", "qc_steady_MPa", 1.0),
    (_T24, r"a ratio of ([\d.]+) to the unbreakable reference: this run", "ratio", 1.0),
    (_T24, r"\*\*Not one grain broke\*\*: (\d+) events", "n_break_events", 1.0),
    (_T24, r"Br over the\s+penetrated layers is ([\d.]+) in 1-2 R and 0.0029",
     "Br_penetrated_1_2R", 1.0),
    (_T24, r"0.0077 in 1-2 R and ([\d.]+) in 2-3 R, because", "Br_penetrated_2_3R", 1.0),
    (_R25, r"Steady q_c ([\d.]+)\s+MPa, a ratio of 1.09 to the unbreakable reference; 74",
     "qc_steady_MPa", 1.0),
    (_R25, r"MPa, a ratio of ([\d.]+) to the unbreakable reference; 74", "ratio", 1.0),
    (_R25, r"reference; (\d+) break events: 22 at\s+switch-on, 13 at entry, and of the 39", "n_break_events",
     1.0),
    (_R25, r"74 break events: (\d+) at\s+switch-on, 13", "events_switch_on", 1.0),
    (_R25, r"switch-on, (\d+) at entry, and of the 39", "events_entry", 1.0),
    (_R25, r"of the (\d+) during penetration 18 in the zone\s+\(46", "events_penetration", 1.0),
    (_R25, r"during penetration (\d+) in the zone\s+\(46", "events_in_zone", 1.0),
    (_R25, r"in the zone\s+\((\d+) %\), 9 beyond 5 R below the tip, 12", "fraction_in_zone", 100.0),
    (_R25, r"\(46 %\), (\d+) beyond 5 R", "events_beyond_5R_below", 1.0),
    (_R25, r"\(46 %\), 9 beyond 5 R below the tip, (\d+) farther than 3 R out",
     "events_elsewhere", 1.0),
    (_R25, r"Br is ([\d.]+) in 1-2 R and 0.011", "Br_penetrated_1_2R", 1.0),
    (_R25, r"0.052 in 1-2 R and ([\d.]+) in 2-3 R\.\s+The printed", "Br_penetrated_2_3R", 1.0),
    (_B25, r"Steady q_c ([\d.]+) MPa, a ratio of 1.02", "qc_steady_MPa", 1.0),
    (_B25, r"a ratio of ([\d.]+) to the\s+unbreakable reference; 10", "ratio", 1.0),
    (_B25, r"reference; (\d+) break events, all during", "n_break_events", 1.0),
    (_B25, r"layers Br is\s+([\d.]+) in 1-2 R and 0.0005", "Br_penetrated_1_2R", 1.0),
    (_B25, r"in 1-2 R and ([\d.]+) in 2-3 R\. It repeats", "Br_penetrated_2_3R", 1.0),
    (_R25, r"80 and (\d+) events, 22 at switch-on", "n_break_events", 1.0),
    (_R25, r"43 and (\d+) % of the penetration breaks", "fraction_in_zone", 100.0),
))

# the zero-break run against the printed reading on the same packing, and
# the band Br's floor it measures
_T24_FLOOR = _cr_piece(_T24, "Br_penetrated_1_2R")
ENTRIES += [
    N(_CR_DOC, r"80 breaks cost that packing ([\d.]+) % of its q_c", CR,
      _cr_drop(_PRINTEDS[:1], (_T24,))),
    N(_CR_DOC, r"\(16.56 against ([\d.]+) MPa\)", CR, _cr_piece(_T24, "qc_steady_MPa")),
    N(_CR_DOC, r"in 1-2 R stands ([\d.]+) times above that floor", CR,
      _cr_times("Br_penetrated_1_2R", _R24, _T24)),
    N("docs/report.md", r"never broke \(bench/criterion_readings,\s+`chamber_truncated_0.5_seed2024`\) reads ([\d.]+) in 1-2 R",
      CR, _T24_FLOOR),
    N("docs/report.md", r"reads 0.0077 in 1-2 R and ([\d.]+) in\s+2-3 R", CR,
      _cr_piece(_T24, "Br_penetrated_2_3R")),
    N(_CR_DOC, r"0.018 only ([\d.]+) times\.", CR,
      _cr_times("Br_penetrated_1_2R", "chamber_peak_truncated_0.5_seed2024", _T24)),
]


def _cr_ratio_of_mean(*names):
    return lambda d: _cr_unbreakable_qc() / _cr_mean_qc(*names)(d)


ENTRIES += [
    N(_CR_DOC, r"1.43 and 1.31, is ([\d.]+) on the seeds' mean", CR, _cr_ratio_of_mean(*_PEAKS)),
    N(_CR_DOC, r"on the seeds' mean q_c \(([\d.]+) MPa\)", CR, _cr_mean_qc(*_PEAKS)),
    N(_CR_DOC, r"the peak reading's mean q_c is (\d+) % below", CR,
      _cr_drop(_PEAKS, _PRINTEDS[:1])),
]

ENTRIES += [
    N(_CR_DOC, r"On the seeds' mean q_c \(([\d.]+) MPa\) its ratio", CR, _cr_mean_qc(*_PRINTEDS)),
    N(_CR_DOC, r"\(16.20 MPa\) its ratio is ([\d.]+),", CR, _cr_ratio_of_mean(*_PRINTEDS)),
    N(_CR_DOC, r"peak reading's mean q_c is (\d+) % lower, and", CR, _cr_drop(_PEAKS, _PRINTEDS)),
    N(_CR_DOC, r"prepared packing\) (\d+) % and 17 % lower", CR,
      _cr_drop(_PEAKS[:1], _PRINTEDS[:1])),
    N(_CR_DOC, r"27 % and (\d+) % lower: the peak", CR, _cr_drop(_PEAKS[1:], _PRINTEDS[1:])),
    N(_CR_DOC, r"\(Br in 2-3 R ([\d.]+) and 0.011\)", CR, _cr_printed("Br_penetrated_2_3R")),
    N(_CR_DOC, r"seeds' mean \(([\d.]+)\s+MPa, a ratio of 1.06\)", CR, _cr_mean_qc(*_BOUNDED)),
    N(_CR_DOC, r"MPa, a ratio of ([\d.]+)\) is the printed", CR, _cr_ratio_of_mean(*_BOUNDED)),
    N(_CR_DOC, r"its mean \(([\d.]+)\s+in 1-2 R, 0.027", CR, _cr_mean("Br_penetrated_1_2R", *_PRINTEDS)),
    N(_CR_DOC, r"in 1-2 R, ([\d.]+) in 2-3 R\) is the number", CR,
      _cr_mean("Br_penetrated_2_3R", *_PRINTEDS)),
]

# the ninth piece: the peak pressure with the Weibull law, seed 2024, against
# the peak reading on the same packing; and the two laws' weak tails (analytic)
_PW24 = "chamber_peak_weibull_seed2024"
ENTRIES += _cr_rows((
    (_PW24, r"Steady q_c ([\d.]+) MPa, a\s+ratio of 1.39", "qc_steady_MPa", 1.0),
    (_PW24, r"ratio of ([\d.]+) to the unbreakable reference; 124", "ratio", 1.0),
    (_PW24, r"reference; (\d+) break events: 11 at\s+switch-on, 16", "n_break_events", 1.0),
    (_PW24, r"124 break events: (\d+) at\s+switch-on", "events_switch_on", 1.0),
    (_PW24, r"switch-on, (\d+) at entry, and of the 97", "events_entry", 1.0),
    (_PW24, r"of the (\d+) during penetration 69", "events_penetration", 1.0),
    (_PW24, r"during penetration (\d+) in the zone\s+\(71", "events_in_zone", 1.0),
    (_PW24, r"in the zone\s+\((\d+) %\), 5 beyond", "fraction_in_zone", 100.0),
    (_PW24, r"\(71 %\), (\d+) beyond 5 R", "events_beyond_5R_below", 1.0),
    (_PW24, r"5 beyond 5 R below the tip, (\d+) farther than 3 R out", "events_elsewhere", 1.0),
    (_PW24, r"Br is ([\d.]+) in 1-2 R and 0.068 in\s+2-3 R\. \*\*It", "Br_penetrated_1_2R", 1.0),
    (_PW24, r"0.121 in 1-2 R and ([\d.]+) in\s+2-3 R\. \*\*It", "Br_penetrated_2_3R", 1.0),
    (_PW24, r"switch-on against 39, (\d+) beyond 5 R against 18", "events_beyond_5R_below", 1.0),
    (_PW24, r"Br in 1-2 R ([\d.]+) against 0.140", "Br_penetrated_1_2R", 1.0),
    (_P24, r"packing \(seed 2024: q_c ([\d.]+) MPa, 151", "qc_steady_MPa", 1.0),
    (_P24, r"q_c 12.12 MPa, (\d+) events\) it keeps", "n_break_events", 1.0),
    (_P24, r"Br in 1-2 R 0.121 against ([\d.]+)\)", "Br_penetrated_1_2R", 1.0),
    (_PW24, r"(\d+) at switch-on against 39", "events_switch_on", 1.0),
    (_P24, r"11 at switch-on against (\d+)", "events_switch_on", 1.0),
    (_P24, r"5 beyond 5 R against (\d+)", "events_beyond_5R_below", 1.0),
    ("oedometer_peak_weibull", r"\(core void\s+ratio ([\d.]+) at 30 MPa against 0.52",
     "e_core_at_30MPa", 1.0),
    ("oedometer_printed", r"ratio 0.28 at 30 MPa against ([\d.]+), Br", "e_core_at_30MPa", 1.0),
    ("oedometer_peak_weibull", r"against 0.52, Br ([\d.]+) against 0.10\)", "Br_at_30MPa", 1.0),
    ("oedometer_printed", r"Br 0.51 against ([\d.]+)\), and its", "Br_at_30MPa", 1.0),
))


def _weibull_shape(cov):
    """Shape k of the Weibull law whose coefficient of variation is cov
    (bisection on sqrt(G(1 + 2/k) / G(1 + 1/k)^2 - 1), decreasing in k)."""
    lo, hi = 0.5, 50.0
    for _ in range(200):
        k = 0.5 * (lo + hi)
        c = math.sqrt(math.gamma(1 + 2 / k) / math.gamma(1 + 1 / k) ** 2 - 1)
        lo, hi = (k, hi) if c > cov else (lo, k)
    return k


def _below_f(law, f, cov=0.36):
    """Fraction (%) of strength draws below f: the printed normal law of mean
    1 redrawn at f <= 0, or the Weibull law of mean 1 and the same CoV."""
    if law == "weibull":
        k = _weibull_shape(cov)
        lam = 1.0 / math.gamma(1 + 1 / k)
        return 100.0 * (1.0 - math.exp(-((f / lam) ** k)))
    phi = lambda x: 0.5 * (1.0 + math.erf((x - 1.0) / (cov * math.sqrt(2.0))))  # noqa: E731
    return 100.0 * (phi(f) - phi(0.0)) / (1.0 - phi(0.0))


_PW_TRI = ("triaxial_peak_weibull", "triaxial_peak_weibull_seed2025")
_PHI_CS_MAX = 33.5        # deg: the calibration's range's top, as the study's acceptance quotes it
ENTRIES += [
    N(_CR_DOC, r"\(0.36,\s+shape ([\d.]+)\)", CR, lambda d: _weibull_shape(0.36)),
    N(_CR_DOC, r"it draws ([\d.]+) % of the grains below f = 0.1", CR,
      lambda d: _below_f("weibull", 0.1)),
    N(_CR_DOC, r"printed normal law's ([\d.]+) % \(redrawn", CR, lambda d: _below_f("normal", 0.1)),
    N(_CR_DOC, r"and ([\d.]+) % below f = 0.2", CR, lambda d: _below_f("weibull", 0.2)),
    N(_CR_DOC, r"below f = 0.2\s+against ([\d.]+) %", CR, lambda d: _below_f("normal", 0.2)),
    N(_CR_DOC, r"below f = 0.4 \(([\d.]+) against", CR, lambda d: _below_f("weibull", 0.4)),
    N(_CR_DOC, r"below f = 0.4 \(4.3 against ([\d.]+) %\)", CR, lambda d: _below_f("normal", 0.4)),
    N(_CR_DOC, r"\(q_c within\s+(\d+) %", CR, _cr_drop((_P24,), (_PW24,))),
    N(_CR_DOC, r"triaxial\s+phi_cs \(([\d.]+) deg, seed mean\)", CR, _cr_mean("phi_cs_deg", *_PW_TRI)),
    N(_CR_DOC, r"seed mean\) lies ([\d.]+) deg above", CR,
      lambda d: _cr_mean("phi_cs_deg", *_PW_TRI)(d) - _PHI_CS_MAX),
    N(_CR_DOC, r"70 % of 97 is (\d+) events", CR,
      lambda d: math.ceil(0.7 * _cr_piece(_PW24, "events_penetration")(d))),
]

# the tenth piece: peak_weibull's second seed, its two seeds together and
# against the peak reading's, and the decision's quotes
_PW25 = "chamber_peak_weibull_seed2025"
_PWS = (_PW24, _PW25)


def _cr_sum(key, *names):
    """A count summed over the pieces."""
    return lambda d: sum(d["runs"][n]["metrics"][key] for n in names)


def _cr_pooled_fraction(*names):
    """In-zone events over penetration events, both summed over the pieces (%)."""
    return lambda d: 100.0 * (_cr_sum("events_in_zone", *names)(d)
                              / _cr_sum("events_penetration", *names)(d))


ENTRIES += _cr_rows((
    (_PW25, r"Steady q_c ([\d.]+) MPa, a ratio of 1.45", "qc_steady_MPa", 1.0),
    (_PW25, r"a ratio of ([\d.]+) to the unbreakable reference; 119", "ratio", 1.0),
    (_PW25, r"reference; (\d+)\s+break events: 11 at switch-on, 14", "n_break_events", 1.0),
    (_PW25, r"119\s+break events: (\d+) at switch-on, 14", "events_switch_on", 1.0),
    (_PW25, r"switch-on, (\d+) at entry, and of the 94", "events_entry", 1.0),
    (_PW25, r"of the (\d+) during\s+penetration 61", "events_penetration", 1.0),
    (_PW25, r"penetration (\d+) in the zone \(65", "events_in_zone", 1.0),
    (_PW25, r"in the zone \((\d+) %\), 10 beyond", "fraction_in_zone", 100.0),
    (_PW25, r"\(65 %\), (\d+) beyond 5 R", "events_beyond_5R_below", 1.0),
    (_PW25, r"10 beyond 5 R below the tip, (\d+) farther", "events_elsewhere", 1.0),
    (_PW25, r"Br is ([\d.]+)\s+in 1-2 R and 0.063", "Br_penetrated_1_2R", 1.0),
    (_PW25, r"0.138\s+in 1-2 R and ([\d.]+) in 2-3 R\. The two", "Br_penetrated_2_3R", 1.0),
    (_PW25, r"124 and (\d+) events, 11", "n_break_events", 1.0),
    (_PW25, r"Br in 1-2 R 0.121 and\s+([\d.]+)\. On", "Br_penetrated_1_2R", 1.0),
    (_PW24, r"missed on the second: (\d+) and 65 %", "fraction_in_zone", 100.0),
    (_PW25, r"missed on the second: 71 and (\d+) %", "fraction_in_zone", 100.0),
    ("chamber_peak_seed2025", r"\(11 and 11 against\s+39 and (\d+)\)", "events_switch_on", 1.0),
    (_PW25, r"fewer beyond 5 R \(5 and (\d+) against", "events_beyond_5R_below", 1.0),
    ("chamber_peak_seed2025", r"against 18 and (\d+)\), puts", "events_beyond_5R_below", 1.0),
    (_P24, r"\(71 against\s+(\d+) %, 65", "fraction_in_zone", 100.0),
    (_PW25, r"55 %, (\d+) against 48 %\)", "fraction_in_zone", 100.0),
    (_P25, r"65 against (\d+) %\), and costs", "fraction_in_zone", 100.0),
))
ENTRIES += [
    N(_CR_DOC, r"On the seeds' mean q_c \(([\d.]+) MPa\) the ratio is", CR, _cr_mean_qc(*_PWS)),
    N(_CR_DOC, r"\(12.23 MPa\) the ratio is ([\d.]+), inside", CR, _cr_ratio_of_mean(*_PWS)),
    N(_CR_DOC, r"65 % of the penetration breaks, (\d+) % of\s+the two seeds'", CR,
      _cr_pooled_fraction(*_PWS)),
    N(_CR_DOC, r"of\s+the two seeds' (\d+) together", CR,
      _cr_sum("events_penetration", *_PWS)),
    N(_CR_DOC, r"\(mean q_c 12.23 against ([\d.]+) MPa, inside", CR, _cr_mean_qc(*_PEAKS)),
    N(_CR_DOC, r"the ratio on both seeds \(([\d.]+) on the mean\)", CR, _cr_ratio_of_mean(*_PWS)),
    N(_CR_DOC, r"no break along the shaft, and\s+(\d+) % of the penetration", CR,
      _cr_pooled_fraction(*_PWS)),
]

# the printed reading with crushing on in the preparation (the study's eleventh
# piece, and docs/cpt.md "Crushing during preparation"), against the printed reading
_PC24 = "chamber_prep_crush_seed2024"
ENTRIES += _cr_rows((
    (_PC24, r"Steady q_c ([\d.]+) MPa, a\s+ratio of 1.05", "qc_steady_MPa", 1.0),
    (_PC24, r"ratio of ([\d.]+) to the unbreakable reference; 82", "ratio", 1.0),
    (_PC24, r"reference; (\d+) break events: 22 during", "n_break_events", 1.0),
    (_PC24, r"82 break events: (\d+) during the", "n_break_events_prep", 1.0),
    (_PC24, r"none at switch-on, (\d+) at entry, and of the 53", "events_entry", 1.0),
    (_PC24, r"and of the (\d+) during\s+penetration 23", "events_penetration", 1.0),
    (_PC24, r"penetration (\d+) in the zone \(43 %\) and 9", "events_in_zone", 1.0),
    (_PC24, r"23 in the zone \((\d+) %\) and 9 beyond", "fraction_in_zone", 100.0),
    (_PC24, r"\(43 %\) and (\d+) beyond 5 R below the tip, none", "events_beyond_5R_below",
     1.0),
    (_PC24, r"Br is ([\d.]+) in 1-2 R and 0.033", "Br_penetrated_1_2R", 1.0),
    (_PC24, r"0.038 in 1-2 R and ([\d.]+) in\s+2-3 R", "Br_penetrated_2_3R", 1.0),
    ("chamber_printed_seed2024", r"\(q_c ([\d.]+)\s+MPa; 22 switch-on", "qc_steady_MPa",
     1.0),
    ("chamber_printed_seed2024", r"MPa; (\d+) switch-on events, 49", "events_switch_on",
     1.0),
    ("chamber_printed_seed2024", r"switch-on events, (\d+) during penetration, 21",
     "events_penetration", 1.0),
    ("chamber_printed_seed2024", r"during penetration, (\d+) of them in the zone",
     "events_in_zone", 1.0),
    ("chamber_printed_seed2024", r"of them in the zone,\s+(\d+) %\)",
     "fraction_in_zone", 100.0),
    ("chamber_printed_seed2024", r"reading's (\d+) breaks at switch-on become",
     "events_switch_on", 1.0),
    (_PC24, r"become (\d+) breaks during the preparation", "n_break_events_prep", 1.0),
))

# the twelfth piece (prep_crush, seed 2025), its seeds against the printed
# reading's, and docs/cpt.md's summary of both
_PC25 = "chamber_prep_crush_seed2025"
_PREP_CRUSH = (_PC24, _PC25)


def _cr_rise(name, than):
    """How much higher (%) the q_c of piece `name` is than that of `than`."""
    return lambda d: 100.0 * (_cr_piece(name, "qc_steady_MPa")(d) / _cr_piece(than, "qc_steady_MPa")(d)
                              - 1.0)


def _cr_seed_spreads(d):
    """How far apart (%) the two seeds' q_c are, for every reading run on both."""
    runs = d["runs"]
    out = []
    for n24 in runs:
        n25 = n24.replace("_seed2024", "_seed2025")
        if (n24.startswith("chamber_") and n24.endswith("_seed2024") and n25 in runs
                and runs[n24]["role"] == "reading"):
            q = sorted(runs[n]["metrics"]["qc_steady_MPa"] for n in (n24, n25))
            out.append(100.0 * (q[1] / q[0] - 1.0))
    return out


ENTRIES += _cr_rows((
    (_PC25, r"Steady\s+q_c ([\d.]+) MPa, a ratio of 0.95", "qc_steady_MPa", 1.0),
    (_PC25, r"a ratio of ([\d.]+) to the unbreakable reference; 69", "ratio", 1.0),
    (_PC25, r"reference; (\d+) break\s+events: 23 during", "n_break_events", 1.0),
    (_PC25, r"69 break\s+events: (\d+) during the preparation", "n_break_events_prep", 1.0),
    (_PC25, r"none at switch-on, (\d+) at entry, and of\s+the 36", "events_entry", 1.0),
    (_PC25, r"and of\s+the (\d+) during penetration 17", "events_penetration", 1.0),
    (_PC25, r"the 36 during penetration (\d+) in the zone \(47 %\)", "events_in_zone", 1.0),
    (_PC25, r"17 in the zone \((\d+) %\) and 5 beyond", "fraction_in_zone", 100.0),
    (_PC25, r"\(47 %\) and (\d+) beyond 5 R below the\s+tip", "events_beyond_5R_below", 1.0),
    (_PC25, r"Br is ([\d.]+) in 1-2 R\s+and 0.006 in 2-3 R\. The breaks", "Br_penetrated_1_2R", 1.0),
    (_PC25, r"0.050 in 1-2 R\s+and ([\d.]+) in 2-3 R", "Br_penetrated_2_3R", 1.0),
    (_R25, r"reading's (\d+) switch-on breaks on this seed", "events_switch_on", 1.0),
    (_PC25, r"on this seed become (\d+) during the", "n_break_events_prep", 1.0),
    (_PC25, r"penetration breaks (\d+) grains against the printed", "events_penetration", 1.0),
    (_R25, r"grains against the printed\s+reading's (\d+), 17", "events_penetration", 1.0),
    (_PC25, r"reading's 39, (\d+) of them in the zone against 18", "events_in_zone", 1.0),
    (_R25, r"in the zone against (\d+) \(47 against", "events_in_zone", 1.0),
    (_PC25, r"against 18 \((\d+) against 46 %\)", "fraction_in_zone", 100.0),
    (_R25, r"\(47 against (\d+) %\)\. Its q_c", "fraction_in_zone", 100.0),
    (_PC25, r"packing seed \(([\d.]+)\s+against 15.83 MPa\)", "qc_steady_MPa", 1.0),
    (_R25, r"packing seed \(18.13\s+against ([\d.]+) MPa\)", "qc_steady_MPa", 1.0),
))


@functools.lru_cache(maxsize=None)
def _evr_table():
    """The error-vs-runtime study's table (the reference chamber's noise)."""
    return json.loads((Path(__file__).resolve().parents[2] / EVR_TABLE).read_text())


def _reference_ratio_sd():
    """The relative sd of the unbreakable/crushable q_c ratio over the four
    reference runs (the error-vs-runtime table): the scatter of two runs' ratio."""
    return _pooled_ratio(_evr_table())[1]


def _single_run_qc_sd():
    """The relative sd of one crushable run's q_c over the same four runs."""
    return _evr_table()["chamber_spread"]["models"]["crushable_ne34"]["rel_std"]["qc_steady_MPa"]


ENTRIES += [
    N(_CR_DOC, r"Its q_c\s+is (\d+) % above the printed reading's", CR, _cr_rise(_PC25, _R25)),
    N(_CR_DOC, r"both differ by ([\d.]+)-10 %", CR, lambda d: min(_cr_seed_spreads(d))),
    N(_CR_DOC, r"both differ by 0.5-(\d+) %", CR, lambda d: max(_cr_seed_spreads(d))),
    N(_CR_DOC, r"\(the first differs by ([\d.]+) %\)", CR,
      lambda d: abs(_cr_rise(_PC24, "chamber_printed_seed2024")(d))),
    N(_CR_DOC, r"this difference is about ([\d.]+) times that scatter", CR,
      lambda d: _cr_rise(_PC25, _R25)(d) / (100.0 * _reference_ratio_sd())),
    N(_CR_DOC, r"On the seeds' means\s+\(([\d.]+) against 16.20 MPa", CR, _cr_mean_qc(*_PREP_CRUSH)),
    N(_CR_DOC, r"\(17.31 against ([\d.]+) MPa, \d+ % apart\)", CR, _cr_mean_qc(*_PRINTEDS)),
    N(_CR_DOC, r"16.20 MPa, (\d+) % apart\)", CR,
      lambda d: 100.0 * (_cr_mean_qc(*_PREP_CRUSH)(d) / _cr_mean_qc(*_PRINTEDS)(d) - 1.0)),
    N(_CR_DOC, r"% apart\) the ratio is ([\d.]+) against the printed", CR,
      _cr_ratio_of_mean(*_PREP_CRUSH)),
    N(_CR_DOC, r"ratio is 1.00 against the printed\s+reading's ([\d.]+), and", CR,
      _cr_ratio_of_mean(*_PRINTEDS)),
    N(_CR_DOC, r"and (\d+) % of the two seeds' 89 penetration", CR, _cr_pooled_fraction(*_PREP_CRUSH)),
    N(_CR_DOC, r"of the two seeds' (\d+) penetration breaks lie in\s+the zone\. Crushing", CR,
      _cr_sum("events_penetration", *_PREP_CRUSH)),
    N(_CR_DOC, r"\(a ratio of ([\d.]+)\s+on its seeds' mean, 45 %", CR, _cr_ratio_of_mean(*_PREP_CRUSH)),
    N(_CR_DOC, r"on its seeds' mean, (\d+) % of the penetration", CR, _cr_pooled_fraction(*_PREP_CRUSH)),
]
ENTRIES += [
    N("docs/cpt.md", pattern, CR, value) for pattern, value in (
        (r"the (\d+) breaks\s+the default run has at switch-on", _cr_printed("events_switch_on")),
        (r"\((\d+) and 23 there, none at switch-on\)", _cr_piece(_PC24, "n_break_events_prep")),
        (r"\(22 and (\d+) there, none at switch-on\)", _cr_piece(_PC25, "n_break_events_prep")),
        (r"one seed's q_c: ([\d.]+) and 18.13", _cr_piece(_PC24, "qc_steady_MPa")),
        (r"one seed's q_c: 16.50 and ([\d.]+)", _cr_piece(_PC25, "qc_steady_MPa")),
        (r"against ([\d.]+) and\s+15.83 MPa", _cr_printed("qc_steady_MPa")),
        (r"against 16.56 and\s+([\d.]+) MPa", _cr_piece(_R25, "qc_steady_MPa")),
        (r"\(([\d.]+) and 15 % higher", lambda d: abs(_cr_rise(_PC24, "chamber_printed_seed2024")(d))),
        (r"\(0.4 and (\d+) % higher", _cr_rise(_PC25, _R25)),
        (r"(\d+) and 47 % of the penetration", _cr_piece(_PC24, "fraction_in_zone", 100.0)),
        (r"43 and (\d+) % of the penetration", _cr_piece(_PC25, "fraction_in_zone", 100.0)),
        (r"in the zone against (\d+) and 46 %", _cr_printed("fraction_in_zone", 100.0)),
        (r"in the zone against 43 and (\d+) %", _cr_piece(_R25, "fraction_in_zone", 100.0)),
    )
]

# the Weibull law's second seed (the study's thirteenth piece) and its two seeds
_W25 = "chamber_weibull_seed2025"
_WEIBULLS = (_W24, _W25)
ENTRIES += _cr_rows((
    (_W25, r"Steady q_c ([\d.]+) MPa, a ratio of 1.03 to the unbreakable\s+reference; 46", "qc_steady_MPa",
     1.0),
    (_W25, r"a ratio of ([\d.]+) to the unbreakable\s+reference; 46", "ratio", 1.0),
    (_W25, r"reference; (\d+) break events: 1 at switch-on", "n_break_events", 1.0),
    (_W25, r"46 break events: (\d+) at switch-on, 8", "events_switch_on", 1.0),
    (_W25, r"1 at switch-on, (\d+) at entry, and of the 37", "events_entry", 1.0),
    (_W25, r"and of the (\d+)\s+during penetration 26", "events_penetration", 1.0),
    (_W25, r"during penetration (\d+) in the zone \(70 %\), 2", "events_in_zone", 1.0),
    (_W25, r"26 in the zone \((\d+) %\), 2 beyond", "fraction_in_zone", 100.0),
    (_W25, r"\(70 %\), (\d+) beyond 5 R below the tip and", "events_beyond_5R_below", 1.0),
    (_W25, r"beyond 5 R below the tip and\s+(\d+) along the shaft again", "events_along_shaft",
     1.0),
    (_W25, r"Br is ([\d.]+) in\s+1-2 R and 0.043", "Br_penetrated_1_2R", 1.0),
    (_W25, r"0.048 in\s+1-2 R and ([\d.]+) in 2-3 R", "Br_penetrated_2_3R", 1.0),
    (_R25, r"\(seed 2025: (\d+) events, 22 at switch-on, 9 beyond", "n_break_events", 1.0),
    (_R25, r"74 events, (\d+) at switch-on, 9 beyond 5 R, 46", "events_switch_on", 1.0),
    (_R25, r"22 at switch-on, (\d+) beyond 5 R, 46 % in the zone\)", "events_beyond_5R_below", 1.0),
    (_R25, r"9 beyond 5 R, (\d+) % in the zone\) the", "fraction_in_zone", 100.0),
    (_W25, r"from the cone \((\d+) at switch-on,", "events_switch_on", 1.0),
    (_W25, r"\(1 at switch-on,\s+(\d+) beyond 5 R\) and keeps", "events_beyond_5R_below", 1.0),
    (_W25, r"`weibull` 38 and (\d+) events and a ratio", "n_break_events", 1.0),
))
ENTRIES += [
    N(_CR_DOC, r"Over both seeds (\d+) % of its 66 penetration", CR, _cr_pooled_fraction(*_WEIBULLS)),
    N(_CR_DOC, r"% of its (\d+) penetration breaks lie in the zone", CR,
      _cr_sum("events_penetration", *_WEIBULLS)),
] + [
    # "on each seed": the one quote must hold for both
    N(_CR_DOC, r"and (\d+) grain breaks along the shaft on each seed", CR,
      _cr_piece(n, "events_along_shaft")) for n in _WEIBULLS
] + [
    N(_CR_DOC, r"q_c\s+is (\d+) % above the printed reading's on this packing", CR,
      _cr_rise(_W25, _R25)),
    N(_CR_DOC, r"on the seeds'\s+mean \(([\d.]+) MPa\) the ratio is 1.06", CR, _cr_mean_qc(*_WEIBULLS)),
    N(_CR_DOC, r"\(16.39 MPa\) the ratio is ([\d.]+), the printed", CR, _cr_ratio_of_mean(*_WEIBULLS)),
    N(_CR_DOC, r"the ratio is 1.06, the printed reading's ([\d.]+)\.", CR,
      _cr_ratio_of_mean(*_PRINTEDS)),
    N(_CR_DOC, r"a ratio of ([\d.]+) on its seeds' mean,\s+`truncated", CR, _cr_ratio_of_mean(*_WEIBULLS)),
]

# the bounded tail's second seed (the study's fourteenth piece): no break on
# either seed, so its two runs are unbreakable runs on the printed packings
_T25 = "chamber_truncated_0.5_seed2025"
_TRUNCATEDS = (_T24, _T25)
ENTRIES += _cr_rows((
    (_T25, r"either\*\*: (\d+) events\. Steady", "n_break_events", 1.0),
    (_T25, r"Steady q_c\s+([\d.]+) MPa, a ratio of 1.03 to the unbreakable reference; Br", "qc_steady_MPa",
     1.0),
    (_T25, r"a ratio of ([\d.]+) to the unbreakable reference; Br over", "ratio", 1.0),
    (_T25, r"penetrated layers is ([\d.]+) in 1-2 R and 0.0004", "Br_penetrated_1_2R", 1.0),
    (_T25, r"0.0091 in 1-2 R and ([\d.]+) in 2-3 R, the floor", "Br_penetrated_2_3R", 1.0),
    (_T25, r"\(15.83 against ([\d.]+) MPa\), 5.7", "qc_steady_MPa", 1.0),
    (_R25, r"\(([\d.]+) against 16.83 MPa\)", "qc_steady_MPa", 1.0),
))
ENTRIES += [
    N(_CR_DOC, r"The two seeds' q_c differ\s+by (\d+) %; on their mean", CR,
      lambda d: abs(_cr_rise(_T24, _T25)(d))),
    N(_CR_DOC, r"on their mean \(([\d.]+) MPa\) the ratio is 1.01", CR, _cr_mean_qc(*_TRUNCATEDS)),
    N(_CR_DOC, r"\(17.18 MPa\) the ratio is ([\d.]+)\. Both", CR, _cr_ratio_of_mean(*_TRUNCATEDS)),
    N(_CR_DOC, r"of q_c on seed 2024 and ([\d.]+) % on seed 2025", CR, _cr_drop((_R25,), (_T25,))),
    N(_CR_DOC, r"cost its packing ([\d.]+) % of q_c on seed 2024", CR,
      _cr_drop(_PRINTEDS[:1], (_T24,))),
    N(_CR_DOC, r"MPa\), ([\d.]+) % on the mean\.", CR, _cr_drop(_PRINTEDS, _TRUNCATEDS)),
    N(_CR_DOC, r"reference chamber's ratio of ([\d.]+) again", EVR_TABLE, lambda d: _pooled_ratio(d)[0]),
    N(_CR_DOC, r"\(crushable ([\d.]+) % below\s+unbreakable\)", EVR_TABLE,
      lambda d: 100.0 * (1.0 - 1.0 / _pooled_ratio(d)[0])),
    N(_CR_DOC, r"the printed reading's Br in 1-2 R \(([\d.]+) on the mean\)", CR,
      _cr_mean("Br_penetrated_1_2R", *_PRINTEDS)),
    N(_CR_DOC, r"on the mean\) stands ([\d.]+)\s+times above the floor", CR,
      lambda d: (_cr_mean("Br_penetrated_1_2R", *_PRINTEDS)(d)
                 / _cr_mean("Br_penetrated_1_2R", *_TRUNCATEDS)(d))),
    N(_CR_DOC, r"the floor's mean \(([\d.]+)\)", CR, _cr_mean("Br_penetrated_1_2R", *_TRUNCATEDS)),
    N(_CR_DOC, r"`truncated_0.5` no break on\s+either seed and ([\d.]+) on its seeds' mean", CR,
      _cr_ratio_of_mean(*_TRUNCATEDS)),
    N(_CR_DOC, r"scattering by ([\d.]+) % \(sd\) the mean", CR, lambda d: 100.0 * _single_run_qc_sd()),
    N(_CR_DOC, r"carries an sd of ([\d.]+) % too", CR, lambda d: 100.0 * _single_run_qc_sd()),
    N(_CR_DOC, r"so 5.7 % stands ([\d.]+) sd from\s+zero", CR,
      lambda d: _cr_drop(_PRINTEDS, _TRUNCATEDS)(d) / (100.0 * _single_run_qc_sd())),
    N(_CR_DOC, r"so ([\d.]+) % stands 1.6 sd", CR, _cr_drop(_PRINTEDS, _TRUNCATEDS)),
]

# the total force at the Coulomb limit, seed 2024 (the fifteenth piece), and
# where its breaks lie against the printed reading's on the same packing
_S24 = "chamber_sliding_seed2024"
BREAKS = "bench/criterion_readings/break_events.json"


def _cr_same_place(name, other, tol):
    """How many break events of piece `name` lie within `tol` R, in radius
    and in depth below the surface, of a break event of piece `other`."""
    def at(d, n):
        e = d[n]
        return np.c_[e["r_over_R"], np.subtract(e["h_over_R"], e["tip_depth_over_R"])]

    def count(d):
        a, b = at(d, name), at(d, other)
        dist = np.sqrt(((a[:, None, :] - b[None, :, :]) ** 2).sum(-1)).min(axis=1)
        return int((dist < tol).sum())
    return count


ENTRIES += _cr_rows((
    (_S24, r"Steady q_c ([\d.]+) MPa, a ratio of 1.12 to the\s+unbreakable reference; 79",
     "qc_steady_MPa", 1.0),
    (_S24, r"a ratio of ([\d.]+) to the\s+unbreakable reference; 79", "ratio", 1.0),
    (_S24, r"reference; (\d+) break events: 22 at switch-on, 8 at entry", "n_break_events", 1.0),
    (_S24, r"79 break events: (\d+) at switch-on, 8 at entry", "events_switch_on", 1.0),
    (_S24, r"22 at switch-on, (\d+) at entry, and\s+of the 49", "events_entry", 1.0),
    (_S24, r"8 at entry, and\s+of the (\d+) during penetration 22", "events_penetration", 1.0),
    (_S24, r"during penetration (\d+) in the zone \(45 %\)", "events_in_zone", 1.0),
    (_S24, r"22 in the zone \((\d+) %\), 9 beyond", "fraction_in_zone", 100.0),
    (_S24, r"\(45 %\), (\d+) beyond 5 R below the\s+tip and 18", "events_beyond_5R_below", 1.0),
    (_S24, r"tip and (\d+) farther than 3 R out, none along the shaft; over the penetrated\s+layers Br is 0.025",
     "events_elsewhere", 1.0),
    (_S24, r"Br is ([\d.]+) in 1-2 R and 0.041", "Br_penetrated_1_2R", 1.0),
    (_S24, r"0.025 in 1-2 R and ([\d.]+) in 2-3 R", "Br_penetrated_2_3R", 1.0),
    (_R24, r"same packing \((\d+)\s+events: 22 at switch-on, 21 of 49",
     "n_break_events", 1.0),
    (_R24, r"80\s+events: (\d+) at switch-on, 21 of 49", "events_switch_on", 1.0),
    (_R24, r"22 at switch-on, (\d+) of 49 penetration", "events_in_zone", 1.0),
    (_R24, r"21 of (\d+) penetration breaks in the zone\)",
     "events_penetration", 1.0),
    (_W24, r"on this packing, 0\s+of (\d+)\.", "n_break_events", 1.0),
))
ENTRIES += [
    N(_CR_DOC, r"\), (\d+) of\s+its 79 events lie within 0.05 R", BREAKS,
      _cr_same_place(_S24, _R24, 0.05)),
    N(_CR_DOC, r"\((\d+) within 0.01 R\)", BREAKS, _cr_same_place(_S24, _R24, 0.01)),
    N(_CR_DOC, r"other packing puts (\d+) of its 74\s+there", BREAKS,
      _cr_same_place(_R25, _R24, 0.05)),
    N(_CR_DOC, r"puts 1 of its (\d+)\s+there", CR, _cr_piece(_R25, "n_break_events")),
    N(_CR_DOC, r"on this packing, (\d+)\s+of 38\.", BREAKS,
      _cr_same_place(_W24, _R24, 0.05)),
    N(_CR_DOC, r"Its q_c is ([\d.]+) % below the printed reading's although", CR,
      _cr_drop((_S24,), (_R24,))),
    N(_CR_DOC, r"break the same grains differ by ([\d.]+) % \(the fifteenth", CR,
      _cr_drop((_S24,), (_R24,))),
]

# the total force's second seed (the sixteenth piece) and its two seeds
_S25 = "chamber_sliding_seed2025"
_SLIDINGS = (_S24, _S25)
ENTRIES += _cr_rows((
    (_S25, r"Steady q_c ([\d.]+) MPa, a ratio of 1.08 to the\s+unbreakable reference; 73",
     "qc_steady_MPa", 1.0),
    (_S25, r"a ratio of ([\d.]+) to the\s+unbreakable reference; 73", "ratio", 1.0),
    (_S25, r"reference; (\d+) break events: 22 at switch-on, 13 at entry, and of the 38", "n_break_events",
     1.0),
    (_S25, r"73 break events: (\d+) at switch-on, 13", "events_switch_on", 1.0),
    (_S25, r"22 at switch-on, (\d+) at entry, and of the 38", "events_entry", 1.0),
    (_S25, r"13 at entry, and of the (\d+) during penetration 18 in the zone \(47", "events_penetration", 1.0),
    (_S25, r"of the 38 during penetration (\d+) in the zone \(47 %\)", "events_in_zone", 1.0),
    (_S25, r"18 in the zone \((\d+) %\), 8 beyond", "fraction_in_zone", 100.0),
    (_S25, r"\(47 %\), (\d+) beyond 5 R below the tip and 12", "events_beyond_5R_below", 1.0),
    (_S25, r"tip and (\d+) farther than 3 R out, none along the shaft; over the penetrated\s+layers Br is 0.056",
     "events_elsewhere", 1.0),
    (_S25, r"Br is ([\d.]+) in 1-2 R and 0.0067", "Br_penetrated_1_2R", 1.0),
    (_S25, r"0.056 in 1-2 R and ([\d.]+) in 2-3 R", "Br_penetrated_2_3R", 1.0),
    (_R25, r"on this packing \((\d+) events, 18 of 39", "n_break_events", 1.0),
    (_R25, r"74 events, (\d+) of 39 penetration breaks", "events_in_zone", 1.0),
    (_R25, r"18 of (\d+) penetration breaks in the zone\), 65", "events_penetration", 1.0),
    (_W25, r"0 of the Weibull law's (\d+) on this packing", "n_break_events", 1.0),
))
ENTRIES += [
    N(_CR_DOC, r"\), (\d+) of its 73 events lie within 0.05 R", BREAKS, _cr_same_place(_S25, _R25, 0.05)),
    N(_CR_DOC, r"of a printed event \((\d+) within 0.01 R\), against", BREAKS,
      _cr_same_place(_S25, _R25, 0.01)),
    N(_CR_DOC, r"against (\d+) for the other packing's printed events", BREAKS,
      _cr_same_place(_S25, _R24, 0.05)),
    N(_CR_DOC, r"and (\d+) of the Weibull law's 46", BREAKS, _cr_same_place(_W25, _R25, 0.05)),
    N(_CR_DOC, r"Here its q_c is ([\d.]+) % above the printed", CR, _cr_rise(_S25, _R25)),
    N(_CR_DOC, r"on the first seed ([\d.]+) % below: two", CR,
      _cr_drop((_S24,), (_R24,))),
    N(_CR_DOC, r"scatter by about the ([\d.]+) % that one run's", CR,
      lambda d: 100.0 * math.sqrt(2.0) * _single_run_qc_sd()),
    N(_CR_DOC, r"that one run's ([\d.]+) % gives the difference", CR, lambda d: 100.0 * _single_run_qc_sd()),
    N(_CR_DOC, r"`force sliding` has (\d+) % of its 87", CR, _cr_pooled_fraction(*_SLIDINGS)),
    N(_CR_DOC, r"% of its (\d+) penetration breaks in the zone and a ratio", CR,
      _cr_sum("events_penetration", *_SLIDINGS)),
    N(_CR_DOC, r"and a ratio of ([\d.]+) on its seeds' mean \(15.76", CR, _cr_ratio_of_mean(*_SLIDINGS)),
    N(_CR_DOC, r"on its seeds' mean \(([\d.]+) MPa; the printed", CR, _cr_mean_qc(*_SLIDINGS)),
    N(_CR_DOC, r"MPa; the printed reading's ([\d.]+)\): it is", CR, _cr_ratio_of_mean(*_PRINTEDS)),
    N(_CR_DOC, r"own grains \((\d+) and 73 events against 80", CR, _cr_piece(_S24, "n_break_events")),
    N(_CR_DOC, r"own grains \(79 and (\d+) events against 80", CR, _cr_piece(_S25, "n_break_events")),
    N(_CR_DOC, r"events against (\d+) and 74\) and 1.10", CR, _cr_printed("n_break_events")),
    N(_CR_DOC, r"events against 80 and (\d+)\) and 1.10", CR, _cr_piece(_R25, "n_break_events")),
    N(_CR_DOC, r"and 74\) and ([\d.]+) on its seeds' mean", CR, _cr_ratio_of_mean(*_SLIDINGS)),
]

# the size term without N (the bracket; the seventeenth piece)
_N24 = "chamber_no_N_seed2024"
ENTRIES += _cr_rows((
    (_N24, r"Steady q_c ([\d.]+) MPa, a ratio of 6.92", "qc_steady_MPa", 1.0),
    (_N24, r"a ratio of ([\d.]+) to the unbreakable reference; 391", "ratio", 1.0),
    (_N24, r"reference; (\d+) break events: 125 at switch-on, 38", "n_break_events", 1.0),
    (_N24, r"391 break events: (\d+) at switch-on", "events_switch_on", 1.0),
    (_N24, r"125 at switch-on, (\d+) at entry, and of the 228", "events_entry", 1.0),
    (_N24, r"of the (\d+) during penetration 144", "events_penetration", 1.0),
    (_N24, r"during penetration (\d+) in the zone \(63", "events_in_zone", 1.0),
    (_N24, r"144 in the zone \((\d+) %\)", "fraction_in_zone", 100.0),
    (_N24, r"\(63 %\), (\d+) beyond 5 R", "events_beyond_5R_below", 1.0),
    (_N24, r"beyond 5 R below the tip and (\d+) along the shaft; over", "events_along_shaft", 1.0),
    (_N24, r"Br is ([\d.]+) in 1-2 R and 0.15 in 2-3 R", "Br_penetrated_1_2R", 1.0),
    (_N24, r"0.35 in 1-2 R and ([\d.]+) in 2-3 R\. It", "Br_penetrated_2_3R", 1.0),
    (_N24, r"\(Br ([\d.]+) in 1-2 R, 10 times", "Br_penetrated_1_2R", 1.0),
    (_N24, r"(\d+) grains break at the step crushing switches on", "events_switch_on", 1.0),
    (_N24, r"on this packing\), (\d+) along the shaft, and the zone", "events_along_shaft", 1.0),
    (_N24, r"the zone takes (\d+) % of the penetration breaks, short", "fraction_in_zone", 100.0),
    (_P24, r"near the peak reading's ([\d.]+) on this packing", "ratio", 1.0),
    (_R24, r"10 times the printed reading's ([\d.]+) on this packing", "Br_penetrated_1_2R", 1.0),
    (_R24, r"switches on \(the printed reading (\d+), the peak", "events_switch_on", 1.0),
    (_P24, r"the peak reading (\d+) on this packing\), 2 along", "events_switch_on", 1.0),
))
ENTRIES += [
    N(_CR_DOC, r"between the printed reading's ([\d.]+) \(seeds' mean\)", CR, _cr_ratio_of_mean(*_PRINTEDS)),
    N(_CR_DOC, r"0.35 in 1-2 R, (\d+) times the printed", CR,
      _cr_times("Br_penetrated_1_2R", _N24, _R24)),
    N(_CR_DOC, r"while q_c falls to (\d+) % of the unbreakable", CR,
      lambda d: 100.0 / _cr_ratio(_N24)(d)),
]

# the bracket's second seed (the eighteenth piece), both seeds, and the decision's last sentences
_N25 = "chamber_no_N_seed2025"
_NOS = (_N24, _N25)
ENTRIES += _cr_rows((
    (_N25, r"Steady q_c ([\d.]+) MPa, a ratio of 6.96", "qc_steady_MPa", 1.0),
    (_N25, r"a ratio of ([\d.]+) to the unbreakable reference; 397", "ratio", 1.0),
    (_N25, r"reference; (\d+) break events: 125 at switch-on, 64", "n_break_events", 1.0),
    (_N25, r"397 break events: (\d+) at switch-on", "events_switch_on", 1.0),
    (_N25, r"125 at switch-on, (\d+) at entry, and of the 208", "events_entry", 1.0),
    (_N25, r"of the (\d+) during penetration 127", "events_penetration", 1.0),
    (_N25, r"during penetration (\d+) in the zone \(61", "events_in_zone", 1.0),
    (_N25, r"127 in the zone \((\d+) %\)", "fraction_in_zone", 100.0),
    (_N25, r"\(61 %\), (\d+) beyond 5 R", "events_beyond_5R_below", 1.0),
    (_N25, r"Br is ([\d.]+) in 1-2 R and 0.13 in 2-3 R", "Br_penetrated_1_2R", 1.0),
    (_N25, r"0.34 in 1-2 R and ([\d.]+) in 2-3 R\. The first", "Br_penetrated_2_3R", 1.0),
))
ENTRIES += [
    N(_CR_DOC, r"the two seeds' q_c differ by ([\d.]+) %, and on their mean \(2.49", CR,
      lambda d: abs(_cr_rise(_N24, _N25)(d))),
    N(_CR_DOC, r"and on their mean \(([\d.]+) MPa\) the ratio is 6.94", CR, _cr_mean_qc(*_NOS)),
    N(_CR_DOC, r"MPa\) the ratio is ([\d.]+), far above", CR, _cr_ratio_of_mean(*_NOS)),
    N(_CR_DOC, r"; (\d+) % of the two seeds' 436 penetration", CR, _cr_pooled_fraction(*_NOS)),
    N(_CR_DOC, r"of the two seeds' (\d+) penetration breaks lie in the zone; over", CR,
      _cr_sum("events_penetration", *_NOS)),
    N(_CR_DOC, r"over both seeds (\d+) grains break at switch-on", CR, _cr_sum("events_switch_on", *_NOS)),
    N(_CR_DOC, r"at switch-on \(the printed reading (\d+)\), 48", CR, _cr_sum("events_switch_on", *_PRINTEDS)),
    N(_CR_DOC, r"reading 44\), (\d+) beyond 5 R below the tip and 2 along", CR,
      _cr_sum("events_beyond_5R_below", *_NOS)),
    N(_CR_DOC, r"tip and (\d+) along the shaft \(both on the first", CR, _cr_sum("events_along_shaft", *_NOS)),
    N(_CR_DOC, r"keeps only the triaxial range \(phi_cs ([\d.]+) deg\)", CR,
      _cr_mean("phi_cs_deg", "triaxial_no_N", "triaxial_no_N_seed2025")),
    N(_CR_DOC, r"over both seeds the printed reading (\d+) %, the peak", CR, _cr_pooled_fraction(*_PRINTEDS)),
    N(_CR_DOC, r"the peak reading (\d+) %, this bracket", CR, _cr_pooled_fraction(*_PEAKS)),
    N(_CR_DOC, r"this bracket (\d+) %\)\.", CR, _cr_pooled_fraction(*_NOS)),
    N(_CR_DOC, r"\(Br ([\d.]+) in 1-2 R on its seeds'\s+mean", CR, _cr_mean("Br_penetrated_1_2R", *_NOS)),
    N(_CR_DOC, r"mean, the printed reading ([\d.]+)\) and loses", CR,
      _cr_mean("Br_penetrated_1_2R", *_PRINTEDS)),
    N(_CR_DOC, r"\(a ratio\s+of ([\d.]+) on its seeds' mean\), with", CR, _cr_ratio_of_mean(*_NOS)),
    N(_CR_DOC, r"with (\d+) % of the penetration breaks in the\s+zone, breaks along", CR,
      _cr_pooled_fraction(*_NOS)),
]

# docs/grain_models.md: its table, printed against peak, from the study's records
_GM_DOC = "docs/grain_models.md"


def _gm_cell(label, k):
    """The k-th number (from 0) in the cells of the table row `label`."""
    # re.escape escapes spaces, which the test turns into runs of whitespace
    return (r"\| " + re.escape(label).replace("\\ ", " ") + r" \|" + r"(?:[^\d\n]*[\d.]+){%d}" % k
            + r"[^\d\n]*([\d.]+)")


_GM_ROWS = {
    "chamber: steady q_c (MPa)": [_cr_printed("qc_steady_MPa"), _cr_piece(_R25, "qc_steady_MPa"),
                                  _cr_piece(_P24, "qc_steady_MPa"),
                                  _cr_piece(_P25, "qc_steady_MPa"),
                                  _cr_piece("chamber_peak_weibull_seed2024", "qc_steady_MPa"),
                                  _cr_piece("chamber_peak_weibull_seed2025", "qc_steady_MPa")],
    "chamber: unbreakable / crushable q_c": [_cr_ratio(_R24), _cr_ratio(_R25),
                                             _cr_ratio_of_mean(*_PRINTEDS),
                                             _cr_ratio(_P24), _cr_ratio(_P25),
                                             _cr_ratio_of_mean(*_PEAKS),
                                             _cr_ratio(_PW24), _cr_ratio(_PW25),
                                             _cr_ratio_of_mean(*_PWS)],
    "chamber: penetration breaks in the zone (r < 3 R, -5 R < h < 1.73 R)": [
        _cr_printed("fraction_in_zone", 100.0), _cr_piece(_R25, "fraction_in_zone", 100.0),
        _cr_piece(_P24, "fraction_in_zone", 100.0),
        _cr_piece(_P25, "fraction_in_zone", 100.0),
        _cr_piece(_PW24, "fraction_in_zone", 100.0), _cr_piece(_PW25, "fraction_in_zone", 100.0)],
    "chamber: breaks beyond 5 R below the tip / along the shaft": [
        _cr_printed("events_beyond_5R_below"), _cr_piece(_R25, "events_beyond_5R_below"),
        _cr_printed("events_along_shaft"), _cr_piece(_R25, "events_along_shaft"),
        _cr_piece(_P24, "events_beyond_5R_below"),
        _cr_piece(_P25, "events_beyond_5R_below"),
        _cr_piece(_P24, "events_along_shaft"),
        _cr_piece(_P25, "events_along_shaft"),
        _cr_piece(_PW24, "events_beyond_5R_below"), _cr_piece(_PW25, "events_beyond_5R_below"),
        _cr_piece(_PW24, "events_along_shaft"), _cr_piece(_PW25, "events_along_shaft")],
    "chamber: breaks at switch-on": [_cr_printed("events_switch_on"), _cr_piece(_R25, "events_switch_on"),
                                     _cr_piece(_P24, "events_switch_on"),
                                     _cr_piece(_P25, "events_switch_on"),
                                     _cr_piece(_PW24, "events_switch_on"),
                                     _cr_piece(_PW25, "events_switch_on")],
    "chamber: Br over the penetrated layers, 1-2 R": [
        _cr_printed("Br_penetrated_1_2R"), _cr_piece(_R25, "Br_penetrated_1_2R"),
        _cr_piece(_P24, "Br_penetrated_1_2R"),
        _cr_piece(_P25, "Br_penetrated_1_2R"),
        _cr_piece(_PW24, "Br_penetrated_1_2R"), _cr_piece(_PW25, "Br_penetrated_1_2R")],
    "oedometer: core void ratio at 10 MPa": [_cr_piece("oedometer_printed", "e_core_at_10MPa"),
                                             _cr_piece("oedometer_peak", "e_core_at_10MPa"),
                                             _cr_piece("oedometer_peak_weibull", "e_core_at_10MPa")],
    "oedometer: core void ratio at 30 MPa": [_cr_piece("oedometer_printed", "e_core_at_30MPa"),
                                             _cr_piece("oedometer_peak", "e_core_at_30MPa"),
                                             _cr_piece("oedometer_peak_weibull", "e_core_at_30MPa")],
    "oedometer: 1 % of the grains broken at (MPa)": [
        _cr_piece("oedometer_printed", "sigma_v_crush_onset_MPa"),
        _cr_piece("oedometer_peak", "sigma_v_crush_onset_MPa"),
        _cr_piece("oedometer_peak_weibull", "sigma_v_crush_onset_MPa")],
    "oedometer: Br at 30 MPa": [_cr_piece("oedometer_printed", "Br_at_30MPa"),
                                _cr_piece("oedometer_peak", "Br_at_30MPa"),
                                _cr_piece("oedometer_peak_weibull", "Br_at_30MPa")],
    "triaxial: phi_cs (deg)": [_cr_piece(n, "phi_cs_deg") for n in (
        "triaxial_printed", "triaxial_printed_seed2025", "triaxial_peak", "triaxial_peak_seed2025",
        "triaxial_peak_weibull", "triaxial_peak_weibull_seed2025")],
    "triaxial: phi_peak (deg)": [_cr_piece(n, "phi_peak_deg") for n in (
        "triaxial_printed", "triaxial_printed_seed2025", "triaxial_peak", "triaxial_peak_seed2025",
        "triaxial_peak_weibull", "triaxial_peak_weibull_seed2025")],
}
ENTRIES += [
    N(_GM_DOC, r"\(q_c 12.23 against ([\d.]+) MPa on the seeds' means", CR, _cr_mean_qc(*_PEAKS)),
    N(_GM_DOC, r"model \(q_c ([\d.]+) against 12.66 MPa", CR, _cr_mean_qc(*_PWS)),
    N(_GM_DOC, r"crushes as much in the first radius beside the cone \(Br\s+([\d.]+) against", CR,
      _cr_mean("Br_penetrated_1_2R", *_PWS)),
    N(_GM_DOC, r"\(Br\s+0.129 against ([\d.]+)\)", CR, _cr_mean("Br_penetrated_1_2R", *_PEAKS)),
    N(_GM_DOC, r"\((\d+) % over both seeds'", CR, _cr_pooled_fraction(*_PWS)),
    N(_GM_DOC, r"over both seeds'\s+(\d+) events", CR,
      _cr_sum("events_penetration", *_PWS)),
    N(_GM_DOC, r"\(([\d.]+) % of\s+them below a tenth", CR, lambda d: _below_f("weibull", 0.1)),
    N(_GM_DOC, r"against the normal law's ([\d.]+) %\)", CR, lambda d: _below_f("normal", 0.1)),
    N(_GM_DOC, r"broken at ([\d.]+) against 0.74 MPa", CR,
      _cr_piece("oedometer_peak_weibull", "sigma_v_crush_onset_MPa")),
    N(_GM_DOC, r"within ([\d.]+) of it at 10 MPa", CR,
      lambda d: abs(_cr_piece("oedometer_peak_weibull", "e_core_at_10MPa")(d)
                    - _cr_piece("oedometer_peak", "e_core_at_10MPa")(d))),
    N(_GM_DOC, r"Br at 30 MPa (\d+) % above\)", CR,
      lambda d: 100.0 * (_cr_piece("oedometer_peak_weibull", "Br_at_30MPa")(d)
                         / _cr_piece("oedometer_peak", "Br_at_30MPa")(d) - 1.0)),
    N(_GM_DOC, r"critical-state angle, ([\d.]+) and 33.9 deg", CR, _cr_piece(_PW_TRI[0], "phi_cs_deg")),
    N(_GM_DOC, r"critical-state angle, 34.0 and ([\d.]+) deg", CR, _cr_piece(_PW_TRI[1], "phi_cs_deg")),
    N(_GM_DOC, r"field, breaks its grains: (\d+) breaks at switch-on", CR,
      _cr_piece(_PW24, "events_switch_on")),
    N(_GM_DOC, r"on each seed against (\d+)-39", CR, _cr_piece(_P25, "events_switch_on")),
    N(_GM_DOC, r"against 36-(\d+),", CR, _cr_piece(_P24, "events_switch_on")),
    N(_GM_DOC, r"\n?5 and (\d+) beyond 5 R below the tip against", CR,
      _cr_piece(_PW25, "events_beyond_5R_below")),
    N(_GM_DOC, r"the tip against 18 and (\d+), and 71", CR, _cr_piece(_P25, "events_beyond_5R_below")),
    N(_GM_DOC, r"penetration breaks in the zone against (\d+) and 48 %", CR,
      _cr_piece(_P24, "fraction_in_zone", 100.0)),
    N(_GM_DOC, r"lies 0.4-([\d.]+) deg above", CR,
      lambda d: _cr_piece(_PW_TRI[0], "phi_cs_deg")(d) - _PHI_CS_MAX),
    N(_GM_DOC, r"printed model's first seed does by ([\d.]+) deg", CR,
      lambda d: _cr_piece("triaxial_printed", "phi_cs_deg")(d) - _PHI_CS_MAX),
]
ENTRIES += [N(_GM_DOC, _gm_cell(label, k), CR, value)
            for label, values in _GM_ROWS.items() for k, value in enumerate(values)]
ENTRIES += [
    N(_GM_DOC, r"pooled unbreakable reference, ([\d.]+) MPa", CR, lambda d: _cr_unbreakable_qc()),
    N(_GM_DOC, r"\(Br ([\d.]+) against 0.043 on", CR, _cr_mean("Br_penetrated_1_2R", *_PEAKS)),
    N(_GM_DOC, r"against ([\d.]+) on the seeds' means\)", CR,
      _cr_mean("Br_penetrated_1_2R", *_PRINTEDS)),
    N(_GM_DOC, r"its q_c is (\d+) % lower on the means", CR, _cr_drop(_PEAKS, _PRINTEDS)),
    N(_GM_DOC, r"on the means, (\d+) % and 17 %", CR, _cr_drop(_PEAKS[:1], _PRINTEDS[:1])),
    N(_GM_DOC, r"27 % and (\d+) % seed by seed", CR, _cr_drop(_PEAKS[1:], _PRINTEDS[1:])),
    N(_GM_DOC, r"seeds agree on the crushing and differ in q_c by (\d+) %", CR,
      lambda d: 100.0 * (d["runs"][_P25]["metrics"]["qc_steady_MPa"]
                         / d["runs"][_P24]["metrics"]["qc_steady_MPa"] - 1.0)),
]

# the printed reading's ratio as the README and model.md quote it ("about N % more")
ENTRIES += [
    N(doc, pattern, CR, lambda d: 100.0 * (_cr_ratio(_R24)(d) - 1.0))
    for doc, pattern in (("README.md", r"resists only about (\d+) % more than crushable"),
                         ("docs/model.md", r"resists only\s+about (\d+) % more than crushable"))
]

FACTS = [
    # the reference page and the study both state the blow-up check's place and defaults
    fact for doc in ("docs/stability.md", "docs/studies/stability.md") for fact in (
        F(doc, r"`inputs/pile_jacking.in` has included `inputs/check_stability.in`",
          _reads("inputs/pile_jacking.in", "include ${inputs}/check_stability.in"),
          "the chamber's jacking block includes the blow-up check"),
        F(doc, r"defaults `move 0.1 overlap 1.5`",
          lambda repo: all(x in (repo / "inputs/check_stability.in").read_text()
                           for x in ("variable stab_move    index 0.1",
                                     "variable stab_overlap index 1.5")),
          "inputs/check_stability.in's defaults"))
] + [
    F("docs/studies/performance.md", r"It ran on a 16-core machine lent on 2026-12-04",
      lambda repo: (repo / "bench/icount/results_scaling_wall_16core.json").exists()
      and "--wall" in (repo / "bench/device/scaling_wall.sh").read_text(),
      "the 16-core --wall results are committed and scaling_wall.sh runs --wall"),
]

# Numbers quoted from a run whose results file is not committed yet: each
# doc carries the marker instead of a current number (a dated, earlier
# measurement may stay beside it). While the file is missing the marker
# must be there; once the file is committed the test fails until the docs
# quote its numbers and DEMO_ENTRIES (patterns to adjust to the new text)
# move into ENTRIES. The demo: `scripts/demo`, then copy
# results/demo/summary.json to bench/demo/summary.json, on quiet cores (8
# minutes on this machine's 2 cores on 2026-12-02; on 2026-12-06, under a
# load average of about 10 from other jobs, 5,040 steps of its preparation
# took 967 s and the run was stopped unfinished).
DEMO_MARK = "to be measured again with the present code: `bench/demo/summary.json`"
PENDING = []     # bench/demo/summary.json is committed: its numbers are in ENTRIES

DEMO_ENTRIES = [
    N("README.md", r"its steady q_c was ([\d.]+) MPa", DEMO, "qc_steady_MPa"),
    N("README.md", r"its steady q_c was [\d.]+ MPa with b h = ([\d.]+) in the fit", DEMO,
      lambda d: d["qc_fit_b"] * d["final_depth_m"]),
    N("README.md", r"with (\d+) breaks and no failed check", DEMO, "n_break_events"),
    N("README.md", r"no failed check, in (\d+) s of wall time", DEMO, "wall_time_s"),
    N("README.md", r"strokes of 30 mm to (\d+) mm into crushable", DEMO, "final_depth_m", 1000.0),
    N("README.md", r"calibration chamber (\d+) pile radii wide", DEMO,
      lambda d: d["R_chamber_m"] / d["R_pile_m"]),
    N("README.md", r"pile radii wide and (\d+) mm high", DEMO, "H_chamber_m", 1000.0),
    N("README.md", r"high, on (\d) MPI ranks", DEMO, "mpi_ranks"),
    N("README.md", r"compressed to (\d+) kPa vertical", DEMO, "prep.sv_boundary_kPa"),
    N("README.md", r"kPa vertical, then (\d+) kPa radial", DEMO, "prep.sr_boundary_kPa"),
    N("README.md", r"expanded to porosity ([\d.]+) at", DEMO, "prep.n_target"),
    N("docs/cpt.md", r"q_c levels off: a = ([\d.]+) \+- [\d.]+ MPa", DEMO, "qc_steady_MPa"),
    N("docs/cpt.md", r"q_c levels off: a = [\d.]+ \+- ([\d.]+) MPa", DEMO, "qc_fit_a_err_MPa"),
    N("docs/cpt.md", r"q_c levels off: a = [\d.]+ \+- [\d.]+ MPa, b = ([\d.]+) 1/m", DEMO,
      "qc_fit_b"),
    N("docs/cpt.md", r"b = [\d.]+ 1/m, b h = ([\d.]+); \d+ breaks", DEMO,
      lambda d: d["qc_fit_b"] * d["final_depth_m"]),
    N("docs/cpt.md", r"b h = [\d.]+; (\d+) breaks, no failed check", DEMO, "n_break_events"),
    N("docs/cpt.md", r"\), (\d+) s for the driver on 2 quiet cores with", DEMO, "wall_time_s"),
    N("docs/studies/error-vs-runtime.md", r"\*\*q_c levels off, a = ([\d.]+) MPa, b h = [\d.]+\*\*", DEMO,
      "qc_steady_MPa"),
    N("docs/studies/error-vs-runtime.md", r"\*\*q_c levels off, a = [\d.]+ MPa, b h = ([\d.]+)\*\*", DEMO,
      lambda d: d["qc_fit_b"] * d["final_depth_m"]),
]

# the demo's numbers, quoted from bench/demo/summary.json (committed 2026-12-06)
ENTRIES += DEMO_ENTRIES
