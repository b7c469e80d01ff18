# SPDX-License-Identifier: GPL-2.0-or-later
"""The particle-size distribution of the whole sample at every state."""


from ..breakage import W_FRACTAL, fractal_psd, psd_curve, sphere_mass
from .common import _plt, _state_label


def _fig_psd(rep, ctx):
    if "psd" not in ctx:
        return
    plt = _plt()
    sizes, F, states, N = ctx["psd_sizes"], ctx["psd"], ctx["states"], ctx["N"]
    lim = fractal_psd(sizes, sizes[0], sizes[-1], W_FRACTAL)
    rep.put("psd", sizes=sizes, F=F, F_limit=lim)
    rep.attrs("psd", d_min=sizes[0], d_max=sizes[-1], N=N, fines="fractal (as the fix)")
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    cmap = plt.get_cmap("viridis")
    for k, s in enumerate(states):
        ax.semilogx(sizes * 1e3, F[k], color=cmap(k / max(len(states) - 1, 1)), lw=1,
                    label=_state_label(s) if k in (0, len(states) - 1) else None)
    ax.semilogx(sizes * 1e3, lim, "k--", lw=1, label="limit grading (w = %g)" % W_FRACTAL)
    ax.set_xlabel("particle size d (mm)")
    ax.set_ylabel("mass fraction finer (-)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    rep.figure(fig, "psd.png", "Particle-size distribution",
               "Grading of the whole sample at every state, the fines of the breaks so far "
               "spread like the limit grading below their parent's smallest fragment (the "
               "fix's 'fractal' convention); d_min = %.3g mm, d_max = %.3g mm (N = %g)."
               % (sizes[0] * 1e3, sizes[-1] * 1e3, N))



def _psd_step(bands, rad, fines, density):
    """The grading of the whole sample at the state into bands["psd_rows"]."""
    m = sphere_mass(2 * rad, density)
    bands["psd_rows"].append(psd_curve(2 * rad, m, 0.0, bands["sizes"], fines=fines,
                                       d_min=bands["d_min"]))
