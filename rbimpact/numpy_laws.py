"""NumPy-vectorised reference implementations of collision laws (no loop over contacts).

They are the baseline of the speed benchmarks (kernel throughput is reported as a ratio
against them) and an independent check of the Numba kernels in the tests. Conventions
are those of DESIGN §3 (normal first, ``v_f = v + W P``, ``P`` the impulse on body A).
"""
import numpy as np

_TOL_ULP = 8.0 * np.finfo(float).eps


def kane_levinson_2d_numpy(v, W, e, mu):
    """Kane & Levinson's law (Kane & Levinson 1985; DESIGN §4) on n 2D contacts at once.

    ``v`` (n, 2) pre-impact relative contact velocities (m/s), ``W`` (n, 2, 2) Delassus
    matrices (1/kg), scalars ``e`` in [0, 1] and ``mu >= 0``. Returns ``P`` (n, 2), the
    impulses on body A (N s). Separating contacts (``v_N >= 0``) and contacts without a
    solution get ``P = 0``, as in ``rbimpact.kernels.kane_levinson.kane_levinson_2d``,
    whose stick trial, slip sign rule and tolerance this follows line by line.
    """
    v = np.asarray(v, dtype=float)
    W = np.asarray(W, dtype=float)
    vn = v[:, 0]
    vt = v[:, 1]
    wnn = W[:, 0, 0]
    wnt = W[:, 0, 1]
    wtt = W[:, 1, 1]
    a = -(1.0 + e) * vn
    impact = vn < 0.0
    P = np.zeros_like(v)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        if mu == 0.0:
            pn = a / wnn
            ok = impact & (wnn > 0.0) & np.isfinite(pn)
            P[:, 0] = np.where(ok, pn, 0.0)
            return P
        det = wnn * wtt - wnt * wnt
        valid = impact & (det > 0.0) & (wnn > 0.0)
        # stick trial: W P* = (a, -v_T)
        sn = (wtt * a + wnt * vt) / det
        st = (-wnn * vt - wnt * a) / det
        stick = (sn >= 0.0) & (np.abs(st) <= mu * sn)
        # slip with P_T = r P_N, r along P*_T first
        r = np.where(st > 0.0, mu, -mu)
        den = wnn + wnt * r
        kn = a / den
        q = wnt + wtt * r
        ok1 = (den > 0.0) & ((vt + kn * q) * r < _TOL_ULP * mu * (np.abs(vt) + kn * np.abs(q)))
        # other sign, only where the first failed (rounding at the stick/slip boundary)
        r2 = -r
        den2 = wnn + wnt * r2
        kn2 = a / den2
        ok2 = (den2 > 0.0) & ((vt + kn2 * (wnt + wtt * r2)) * r2 < 0.0)
        slip_n = np.where(ok1, kn, kn2)
        slip_r = np.where(ok1, r, r2)
        pn = np.where(stick, sn, slip_n)
        pt = np.where(stick, st, slip_r * slip_n)
        ok = valid & (stick | ok1 | ok2) & np.isfinite(pn) & np.isfinite(pt)
    P[:, 0] = np.where(ok, pn, 0.0)
    P[:, 1] = np.where(ok, pt, 0.0)
    return P
