# SPDX-License-Identifier: GPL-2.0-or-later
"""Direction of the major principal stress in the (r, z) plane and its
rotation through a run (issue 10 item 2).

Definition. At a point with cylindrical components sigma_r, sigma_z and
tau_rz (compression positive), the major principal direction of the
(r, z) sub-tensor ``[[sigma_r, tau_rz], [tau_rz, sigma_z]]`` makes the angle

    psi = 0.5 atan2(2 tau_rz, sigma_z - sigma_r)

with the vertical, positive when it tilts from +z towards +r (away from the
pile axis, upwards). psi = 0: the major stress is vertical (the prepared,
K0-like state); psi = +-90: horizontal (radial). The sub-tensor is used,
not the 3-D major axis projected on the plane, because sigma_theta is a
principal stress of an axisymmetric field: the (r, z) rotation is the one
the tip drives, and a sigma_theta that overtakes sigma_r and sigma_z must
not count as a jump of the axis.

An axis is a line, so psi is defined modulo 180 degrees. Through a series
of states the rotation is unwrapped continuously: each step adds the
multiple of 180 degrees that makes it the smallest change, i.e. a change
in (-90, 90]. The unwrapped series minus its first value is the rotation
relative to the initial state; it can exceed 180 degrees, as it does
around piles. This needs states close enough in time that the axis turns
by less than 90 degrees between two of them; a larger real step is taken
as the opposite, smaller one (aliasing). With snapshots at the end of
every push and pause, keep strokes short next to the distances over which
the field turns (a fraction of R around the tip).
"""

import numpy as np

__all__ = ["major_axis_angle", "unwrap_axis", "axis_rotation"]


def major_axis_angle(sigma_r, sigma_z, tau_rz):
    """psi [degrees, in (-90, 90]]: angle of the major principal direction of
    the (r, z) stress from the vertical, + towards +r (module doc)."""
    sr = np.asarray(sigma_r, dtype=float)
    sz = np.asarray(sigma_z, dtype=float)
    t = np.asarray(tau_rz, dtype=float)
    psi = 0.5 * np.degrees(np.arctan2(2.0 * t, sz - sr))
    # atan2 returns (-180, 180]; halve it into (-90, 90]
    return np.where(psi <= -90.0, psi + 180.0, psi)


def unwrap_axis(psi, axis=0):
    """Unwrap axis angles [degrees] along ``axis``: each step becomes the
    change in (-90, 90] equal to it modulo 180 degrees. NaNs (points
    without a stress) stay NaN and the next finite value continues from the
    last finite one."""
    psi = np.moveaxis(np.asarray(psi, dtype=float), axis, 0)
    out = np.full(psi.shape, np.nan)
    if psi.shape[0] == 0:
        return np.moveaxis(out, 0, axis)
    last = psi[0].copy()
    out[0] = last
    for k in range(1, psi.shape[0]):        # loop over states, vectorised over points
        step = np.mod(psi[k] - last + 90.0, 180.0) - 90.0
        step = np.where(step == -90.0, 90.0, step)
        now = np.where(np.isfinite(last), last + step, psi[k])
        out[k] = now
        last = np.where(np.isfinite(now), now, last)
    return np.moveaxis(out, 0, axis)


def axis_rotation(psi, axis=0):
    """Rotation of the major axis relative to the first state [degrees]:
    :func:`unwrap_axis` minus its first value (0 for the first state)."""
    u = unwrap_axis(psi, axis)
    first = np.take(u, [0], axis=axis)
    return u - first
