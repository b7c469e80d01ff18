# SPDX-License-Identifier: GPL-2.0-or-later
"""ParaView's picture of the run's VTK series (crushpost.paraview_state run
by scripts/pvbatch) and its state file."""

import os
import subprocess
import time


def _paraview(rep, ctx):
    # the run's VTK series (--vtk particles) drawn by ParaView itself:
    # paraview_state.py under scripts/pvbatch (docs/report.md, "ParaView")
    from .. import paraview_state
    grains = paraview_state.grain_files(rep.run)
    if not grains:
        rep.skip("ParaView picture", "no %s (run with --vtk particles)"
                 % os.path.join(rep.run, paraview_state.GRAINS_GLOB))
        return
    wrapper = paraview_state.wrapper()
    if not os.path.isfile(wrapper):
        rep.skip("ParaView picture", "%s: no such file (ParaView's wrapper, docs/install.md)"
                 % wrapper)
        return
    name = "paraview.png"
    png = os.path.join(rep.out, name)
    if os.path.exists(png):
        os.remove(png)
    t0 = time.time()
    try:
        res = paraview_state.render(rep.run, png=png, state=os.path.join(rep.out, "paraview.pvsm"))
    except (OSError, subprocess.TimeoutExpired) as exc:
        rep.skip("ParaView picture", "%s: %s" % (wrapper, exc))
        return
    if res.returncode != 0 or not os.path.isfile(png):
        last = [line for line in (res.stderr or "").splitlines() if line.strip()][-1:]
        rep.skip("ParaView picture", "%s exited %d%s" % (wrapper, res.returncode,
                                                         (": " + last[0]) if last else ""))
        return
    rep.settings.append(("ParaView picture", "%d VTK steps, %.1f s" % (len(grains),
                                                                       time.time() - t0)))
    step = os.path.basename(grains[-1])
    rep.figures.append((name, "The grains in ParaView",
                        "The last VTK step (%s) drawn by ParaView (crushpost/paraview_state.py "
                        "under scripts/pvbatch): the whole grains of the half y >= 0 seen from -y, "
                        "i.e. cut by the plane y = 0 through the pile axis, coloured by the mean stress p = tr/3 "
                        "(kPa, compression positive), the strength sigma_lim (MPa) and the "
                        "generation; the meshes coloured by their normal stress. The ParaView "
                        "state is paraview.pvsm (File > Load State)." % step))
