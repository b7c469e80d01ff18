# SPDX-License-Identifier: GPL-2.0-or-later
"""The numbers the report reads from the LIGGGHTS log: mass balance, lost
atoms, the count of break events (at the first step of jacking, before
it) and the fix's Br of the whole sample."""

import re

import numpy as np

from ..thermo import parse_log


def _log_numbers(rep, ctx):
    text = ctx["log"]
    if text is None:
        return
    blocks = [b for b in parse_log(text) if "qc" in b and "Atoms" in b]
    lost = re.findall(r"^ERROR.*Lost atoms: original (\d+) current (\d+)", text, re.M)
    if lost:
        rep.head["lost_atoms"] = int(lost[-1][0]) - int(lost[-1][1])
        rep.head_notes["lost_atoms"] = "the run stopped: LIGGGHTS' 'Lost atoms' error in the log"
    if not blocks:
        rep.skip("mass balance", "%s: no thermo block of the jacking (columns qc, Atoms)"
                 % rep.path("log.liggghts"))
        return
    first, last = blocks[0], blocks[-1]
    if "M_grains" in first and "fines" in last:
        # with crushing on in the preparation (cpt_demo --crush-in-prep) the
        # fix's fines start the jacking above 0: M_0 is grains + fines then
        m0 = first["M_grains"][0] + (first["fines"][0] if "fines" in first else 0.0)
        err = abs(last["M_grains"][-1] + last["fines"][-1] - m0) / m0
        rep.head["mass_balance_rel_error"] = float(err)
        rep.head_notes["mass_balance_rel_error"] = (
            "|M_grains + fines - M_0| / M_0 from the log's thermo output (M_0 = M_grains + "
            "fines at the start of jacking)")
        ctx["M0"] = float(m0)
    if "n_break" in last:
        n_break = int(last["n_break"][-1])
        rep.head["n_break_events"] = n_break
        # breaks before jacking (crushing on in the preparation) are in the
        # fix's count at the jacking's first row, and their fragments in Atoms
        n_break0 = int(first["n_break"][0]) if "n_break" in first else 0
        if "lost_atoms" not in rep.head:
            expected = int(first["Atoms"][0]) + 13 * (n_break - n_break0)
            rep.head["lost_atoms"] = expected - int(last["Atoms"][-1])
            rep.head_notes["lost_atoms"] = (
                "atoms at the start of jacking + 13 per break - atoms at the end (log)")
        events = ctx["events"]
        if events is not None and "Step" in first:
            # crushing is switched on with the jacking: the weakest grains of
            # the strength scatter (f_p far below 1, F_lim ~ f_p^3) are already
            # loaded past their limit by the prepared state and break at the
            # first step, wherever they are, not because of the pile
            start = int(first["Step"][0])
            ctx["jack_first_step"] = start + 1
            rep.head["n_break_events_first_step"] = int(np.count_nonzero(events["step"] == start + 1))
            rep.head_notes["n_break_events_first_step"] = (
                "break events at the first step of jacking (step %d), when crushing is switched "
                "on: grains the prepared state already loads past their limit, not the pile's; "
                "counted in n_break_events and in Br" % (start + 1))
            n_prep = int(np.count_nonzero(events["step"] <= start))
            if n_prep:
                rep.head["n_break_events_prep"] = n_prep
                rep.head_notes["n_break_events_prep"] = (
                    "break events before jacking (step <= %d): crushing on in the preparation "
                    "(cpt_demo --crush-in-prep); counted in n_break_events and in Br" % start)
    if "Br" in last:
        rep.head["Br_sample"] = float(last["Br"][-1])
        rep.head_notes["Br_sample"] = "the fix's bounded Br of the whole sample at the end (log)"
