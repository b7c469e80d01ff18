# SPDX-License-Identifier: GPL-2.0-or-later
"""Stress measures of the field: invariants, cylindrical components, particle
and measurement-sphere stresses, and ring volume averages (docs/model.md §4.6, §4.7).

Sign convention: compression positive (geomechanics), unless a function is
called with ``compression_positive=False``. A contact force ``F^c`` handed to
these functions is always the force acting ON the particle whose centre the
vector (``s^c`` or ``L^c``) starts from. With that force the literal sums
``s (x) F`` and ``F (x) L`` are tension-positive, so they are negated.

Units: forces [N], lengths [m], volumes [m^3] give stresses [Pa]; any
consistent set works.
"""

from typing import NamedTuple

import numpy as np

__all__ = [
    "Invariants", "invariants", "cylindrical_basis", "to_cylindrical_tensor",
    "to_cylindrical", "pair_contact_terms", "particle_stress", "sphere_stress",
    "sphere_ring_volume", "ring_average", "ring_averages",
]


def _sym(sigma):
    return 0.5 * (sigma + np.swapaxes(sigma, -1, -2))


class Invariants(NamedTuple):
    """Stress invariants of a (stack of) 3x3 tensors.

    p : mean stress tr(sigma)/3 [stress].
    q : deviator stress sqrt(3/2) ||s|| [stress]; sigma_1 - sigma_3 in triaxial.
    principal : (..., 3) principal stresses sorted sigma_1 >= sigma_2 >= sigma_3.
    theta_major : angle [degrees, 0..90] between the major principal axis
        (direction of sigma_1) and the vertical z axis.
    """
    p: np.ndarray
    q: np.ndarray
    principal: np.ndarray
    theta_major: np.ndarray


def invariants(sigma):
    """p, q, principal stresses and major-axis tilt of ``sigma`` (..., 3, 3).

    Uses the symmetric part of ``sigma`` (particle stresses of non-rotating
    grains need not be symmetric). "Major" is the algebraically largest
    principal stress, i.e. the most compressive one with compression positive.
    """
    sig = _sym(np.asarray(sigma, dtype=float))
    if sig.shape[-2:] != (3, 3):
        raise ValueError("sigma must have shape (..., 3, 3)")
    p = np.trace(sig, axis1=-2, axis2=-1) / 3.0
    dev = sig - p[..., None, None] * np.eye(3)
    # q = sqrt(3 J2) = sqrt(3/2 s:s); the paper's sqrt(2/3) is a misprint.
    q = np.sqrt(1.5 * np.sum(dev * dev, axis=(-2, -1)))
    vals, vecs = np.linalg.eigh(sig)
    principal = vals[..., ::-1]
    nz = np.abs(vecs[..., 2, -1])
    theta = np.degrees(np.arccos(np.clip(nz, 0.0, 1.0)))
    return Invariants(p, q, principal, theta)


def cylindrical_basis(x, y, axis_xy=(0.0, 0.0)):
    """Rotation matrices (..., 3, 3) whose rows are e_r, e_theta, e_z at (x, y).

    ``axis_xy`` is the (x, y) of the vertical axis (the pile axis). On the
    axis itself the angle atan2(0, 0) = 0 is used.
    """
    theta = np.arctan2(np.asarray(y, dtype=float) - axis_xy[1],
                       np.asarray(x, dtype=float) - axis_xy[0])
    c, s = np.cos(theta), np.sin(theta)
    z0, one = np.zeros_like(c), np.ones_like(c)
    return np.stack([np.stack([c, s, z0], -1),
                     np.stack([-s, c, z0], -1),
                     np.stack([z0, z0, one], -1)], -2)


def to_cylindrical_tensor(sigma, x, y, axis_xy=(0.0, 0.0)):
    """Tensors (..., 3, 3) expressed in the local (r, theta, z) basis at (x, y)."""
    qmat = cylindrical_basis(x, y, axis_xy)
    sigma = np.asarray(sigma, dtype=float)
    return np.einsum("...ik,...kl,...jl->...ij", qmat, sigma, qmat)


def to_cylindrical(sigma, x, y, axis_xy=(0.0, 0.0)):
    """Cylindrical components of Cartesian tensors located at (x, y).

    Returns ``(sigma_r, sigma_theta, sigma_z, tau_rz)``, arrays of the
    broadcast shape of ``sigma[..., 0, 0]``, ``x``, ``y`` [stress].
    ``tau_rz`` is taken from the symmetric part.
    """
    cyl = to_cylindrical_tensor(sigma, x, y, axis_xy)
    return (cyl[..., 0, 0], cyl[..., 1, 1], cyl[..., 2, 2],
            0.5 * (cyl[..., 0, 2] + cyl[..., 2, 0]))


def pair_contact_terms(i, j, x, contact_point, force_on_i):
    """Expand pair contacts into per-particle terms for :func:`particle_stress`.

    Parameters
    ----------
    i, j : (n_c,) particle indices of each contact; ``j < 0`` marks a wall
        (no second particle).
    x : (n_p, 3) particle centres [m].
    contact_point : (n_c, 3) contact points [m].
    force_on_i : (n_c, 3) force on particle ``i`` from ``j`` (or the wall) [N].

    Returns
    -------
    (index, s, force) with one row per particle side of each contact:
    ``s`` = contact point - particle centre; ``force`` on that particle
    (Newton's third law gives ``-force_on_i`` on ``j``).
    """
    i = np.asarray(i, dtype=np.int64)
    j = np.asarray(j, dtype=np.int64)
    x = np.asarray(x, dtype=float)
    xc = np.asarray(contact_point, dtype=float)
    f = np.asarray(force_on_i, dtype=float)
    pj = j >= 0
    index = np.concatenate([i, j[pj]])
    s = np.concatenate([xc - x[i], xc[pj] - x[j[pj]]])
    force = np.concatenate([f, -f[pj]])
    return index, s, force


def particle_stress(index, s, forces, volumes, compression_positive=True):
    """Per-particle stress ``sigma_p = (1/V_p) sum_c s^c (x) F^c`` (docs/model.md §4.7).

    Parameters
    ----------
    index : (n_c,) particle index of each term, in ``[0, n_p)``.
    s : (n_c, 3) vector from the particle centre to the contact point [m].
    forces : (n_c, 3) contact force acting on that particle [N].
    volumes : (n_p,) particle volumes V_p [m^3].
    compression_positive : negate the literal sum (default True).

    Returns
    -------
    (n_p, 3, 3) stresses [Pa], ``sigma[p, i, j] = sum s_i F_j / V_p``; not
    symmetrised. Particles without contacts get zero.
    """
    index = np.asarray(index, dtype=np.int64)
    s = np.asarray(s, dtype=float).reshape(-1, 3)
    forces = np.asarray(forces, dtype=float).reshape(-1, 3)
    volumes = np.asarray(volumes, dtype=float)
    n = volumes.size
    out = np.empty((n, 3, 3))
    # one bincount per component: np.add.at is slow on millions of terms
    for a in range(3):
        for b in range(3):
            out[:, a, b] = np.bincount(index, weights=s[:, a] * forces[:, b], minlength=n)
    sign = -1.0 if compression_positive else 1.0
    return out * (sign / volumes[:, None, None])


def sphere_stress(branch_vectors, forces, volume, compression_positive=True):
    """Measurement-sphere stress ``sigma = (1/V) sum_c F^c (x) L^c`` (docs/model.md §4.6).

    Parameters
    ----------
    branch_vectors : (n_c, 3) L^c = x_q - x_p, from the centre of particle p
        to that of its partner q (for a wall, to the contact point) [m].
        Each contact counted once.
    forces : (n_c, 3) force on particle p from q [N].
    volume : volume V of the measurement sphere [m^3].
    compression_positive : negate the literal sum (default True).

    Returns
    -------
    (3, 3) stress [Pa], ``sigma[i, j] = sum F_i L_j / V``.
    """
    lv = np.asarray(branch_vectors, dtype=float).reshape(-1, 3)
    f = np.asarray(forces, dtype=float).reshape(-1, 3)
    sign = -1.0 if compression_positive else 1.0
    return sign * np.einsum("ci,cj->ij", f, lv) / float(volume)


# --------------------------------------------------------------------------
# sphere / annular-ring intersection volume
# --------------------------------------------------------------------------

_GL_T, _GL_W = np.polynomial.legendre.leggauss(16)


def _disc_overlap(a, r, d):
    """Area common to a disc of radius a and one of radius r, centres d apart."""
    a, r, d = np.broadcast_arrays(a, r, d)
    out = np.zeros(a.shape)
    inside = d <= np.abs(r - a)
    out[inside] = np.pi * np.minimum(a, r)[inside] ** 2
    lens = (~inside) & (d < a + r)
    if np.any(lens):
        al, rl, dl = a[lens], r[lens], d[lens]
        c1 = np.clip((dl * dl + al * al - rl * rl) / (2.0 * dl * al), -1.0, 1.0)
        c2 = np.clip((dl * dl + rl * rl - al * al) / (2.0 * dl * rl), -1.0, 1.0)
        k = (-dl + al + rl) * (dl + al - rl) * (dl - al + rl) * (dl + al + rl)
        out[lens] = (al * al * np.arccos(c1) + rl * rl * np.arccos(c2)
                     - 0.5 * np.sqrt(np.maximum(k, 0.0)))
    return out


def _cut_volume(rho, zc, rad, r_in, r_out, z_lo, z_hi):
    """Quadrature for spheres that the ring boundaries cut.

    Slices at height z are discs of radius a = R cos(theta), z = zc + R sin(theta);
    the disc/annulus area is exact, and the theta integral is split where a
    slice becomes tangent to a ring circle (kinks of the integrand), so
    Gauss-Legendre on each piece converges fast.
    """
    th_lo = np.arcsin(np.clip((z_lo - zc) / rad, -1.0, 1.0))
    th_hi = np.arcsin(np.clip((z_hi - zc) / rad, -1.0, 1.0))
    cands = np.stack([np.abs(r_out - rho), r_out + rho,
                      np.abs(r_in - rho), r_in + rho], -1) / rad[:, None]
    ang = np.arccos(np.clip(cands, 0.0, 1.0))
    bps = np.concatenate([ang, -ang, th_lo[:, None], th_hi[:, None]], -1)
    bps = np.sort(np.clip(bps, th_lo[:, None], th_hi[:, None]), axis=-1)
    mid = 0.5 * (bps[:, 1:] + bps[:, :-1])
    half = 0.5 * (bps[:, 1:] - bps[:, :-1])
    th = mid[..., None] + half[..., None] * _GL_T
    a = rad[:, None, None] * np.cos(th)
    dd = np.broadcast_to(rho[:, None, None], a.shape)
    area = _disc_overlap(a, r_out, dd)
    if r_in > 0:
        area = area - _disc_overlap(a, r_in, dd)
    f = area * a  # dz = R cos(theta) d(theta) = a d(theta)
    return np.einsum("psq,q,ps->p", f, _GL_W, half)


def sphere_ring_volume(centres, radii, r_in, r_out, z_lo, z_hi,
                       axis_xy=(0.0, 0.0), chunk=20000):
    """Volume of each sphere that lies inside the annular ring
    ``r_in <= r <= r_out``, ``z_lo <= z <= z_hi`` around a vertical axis.

    Parameters
    ----------
    centres : (n, 3) sphere centres [m]; radii : (n,) [m].
    r_in, r_out : ring radii measured from the axis at ``axis_xy`` [m]
        (``r_in = 0`` gives a full cylinder).
    z_lo, z_hi : ring height range [m].

    Returns
    -------
    (n,) volumes [m^3]. Spheres fully inside or outside are exact; cut ones
    are integrated numerically to about 1e-9 relative accuracy.
    """
    if not (0 <= r_in < r_out and z_lo < z_hi):
        raise ValueError("need 0 <= r_in < r_out and z_lo < z_hi")
    c = np.asarray(centres, dtype=float).reshape(-1, 3)
    rad = np.broadcast_to(np.asarray(radii, dtype=float), (c.shape[0],))
    rho = np.hypot(c[:, 0] - axis_xy[0], c[:, 1] - axis_xy[1])
    zc = c[:, 2]
    vol = np.zeros(c.shape[0])
    touches = ((rho - rad < r_out) & (rho + rad > r_in)
               & (zc - rad < z_hi) & (zc + rad > z_lo))
    full = (touches & (rho - rad >= r_in) & (rho + rad <= r_out)
            & (zc - rad >= z_lo) & (zc + rad <= z_hi))
    vol[full] = 4.0 / 3.0 * np.pi * rad[full] ** 3
    cut = np.nonzero(touches & ~full)[0]
    for k in range(0, cut.size, chunk):
        sel = cut[k:k + chunk]
        vol[sel] = _cut_volume(rho[sel], zc[sel], rad[sel], r_in, r_out, z_lo, z_hi)
    return vol


def ring_average(sigma_p, centres, radii, r_in, r_out, z_lo, z_hi,
                 axis_xy=(0.0, 0.0), frame="cylindrical", sector=360.0):
    """Volume-averaged stress of one annular ring (docs/model.md §4.7).

    ``sigma_ring = (1/V_ring) sum_p V_p,in sigma_p`` where ``V_p,in`` is the
    part of particle p inside the ring and ``V_ring = (sector/360) pi
    (r_out^2 - r_in^2) (z_hi - z_lo)``: voids carry no stress, so this is the
    average over the whole ring volume. ``sector`` (degrees): the simulated
    sector of a chamber bounded by symmetry planes (180, 90), whose grains
    fill only that part of the ring (they never cross the planes).

    Parameters
    ----------
    sigma_p : (n, 3, 3) Cartesian particle stresses [Pa].
    centres, radii, r_in, r_out, z_lo, z_hi, axis_xy : see
        :func:`sphere_ring_volume`.
    sector : degrees of the ring the particles fill (360: the whole ring;
        180 or 90 for a chamber sector bounded by symmetry planes through the
        axis). The particles' volumes are intersected with the whole ring,
        as they lie in the sector.
    frame : "cylindrical" (default) rotates each particle's tensor to the
        (r, theta, z) basis at its centre before averaging, so the result's
        [0,0], [1,1], [2,2], [0,2] are sigma_r, sigma_theta, sigma_z, tau_rz.
        Averaging Cartesian tensors around a full ring would mix sigma_r and
        sigma_theta. "cartesian" averages the tensors as given.

    Returns
    -------
    (3, 3) averaged stress [Pa] in the chosen basis.
    """
    sigma_p = np.asarray(sigma_p, dtype=float)
    c = np.asarray(centres, dtype=float).reshape(-1, 3)
    w = sphere_ring_volume(c, radii, r_in, r_out, z_lo, z_hi, axis_xy)
    sel = w > 0
    sig = sigma_p[sel]
    if frame == "cylindrical":
        sig = to_cylindrical_tensor(sig, c[sel, 0], c[sel, 1], axis_xy)
    elif frame != "cartesian":
        raise ValueError("frame must be 'cylindrical' or 'cartesian'")
    if not 0.0 < sector <= 360.0:
        raise ValueError("sector must be in (0, 360] degrees, got %r" % (sector,))
    v_ring = sector / 360.0 * np.pi * (r_out ** 2 - r_in ** 2) * (z_hi - z_lo)
    return np.einsum("p,pij->ij", w[sel], sig) / v_ring


def ring_averages(sigma_p, centres, radii, r_edges, z_edges,
                  axis_xy=(0.0, 0.0), frame="cylindrical", sector=360.0):
    """:func:`ring_average` on the grid of rings ``r_edges`` x ``z_edges`` [m]
    (``sector`` as there).

    Returns (len(r_edges)-1, len(z_edges)-1, 3, 3) stresses [Pa].
    """
    r_edges = np.asarray(r_edges, dtype=float)
    z_edges = np.asarray(z_edges, dtype=float)
    out = np.zeros((r_edges.size - 1, z_edges.size - 1, 3, 3))
    for a in range(r_edges.size - 1):
        for b in range(z_edges.size - 1):
            out[a, b] = ring_average(sigma_p, centres, radii, r_edges[a],
                                     r_edges[a + 1], z_edges[b], z_edges[b + 1],
                                     axis_xy, frame, sector)
    return out
