"""Brach's impulse-ratio collision law (R. M. Brach, *Mechanical Impact Dynamics*, Wiley 1991).

Contact-space conventions (DESIGN §3): normal first ``v = (v_N, v_T[, v_T2])`` (m/s),
``W`` the Delassus matrix (1/kg), ``P`` the impulse on body A (N s), ``v_f = v + W P``.
Parameters read from ``params``: ``P_E`` (e in [-1, 1]), ``P_MU`` (mu >= 0),
``P_ET`` (e_t in [-1, 1]; 0 gives Kane & Levinson's law in 2D).

Equations (DESIGN §4), with ``a = -(1 + e) v_N >= 0``:

1. Target ``v_f* = (-e v_N, -e_t v_T)``, ``P* = W^-1 (v_f* - v)``. If ``P*_N >= 0`` and
   ``|P*_T| <= mu P*_N`` (i.e. the ratio ``|r0| = |P*_T| / P*_N <= mu``), ``P = P*``:
   the target is reached without the cone limiting it (``MODE_STICK``).
2. Else the ratio is clamped on the cone: ``r = mu P*_T / |P*_T|`` (2D: ``mu sign(P*_T)``),
   ``P_N = a / (W_NN + W_NT . r)``, ``P_T = r P_N`` (``MODE_SLIP``). For ``P*_N > 0`` this is
   Brach's ``mu r0 / |r0|``; for ``P*_N <= 0`` the ratio is unbounded and the direction
   of ``P*_T`` is its continuous extension through ``P*_N = 0`` (taking the sign of ``r0``
   there would flip the friction against the tangential target). With this choice
   and ``e_t = 0`` the law equals Kane & Levinson in 2D (both always have a solution for
   SPD ``W``).
   If ``P*_T = 0`` (only possible for ``P*_N <= 0`` when ``e = -1``), ``r = 0``.

Numerics: the target ``P*`` is solved as in Kane & Levinson (2D: Cramer's rule with
Kahan's FMA determinants, a few ulps componentwise; 3D: ``common.spd3_solve``, exact SPD
test up to cond ~1e15 and a backward-stable solve), so ``v_f*`` is met to round-off of
``|v| + ||W|| |P|`` however ill-conditioned ``W`` is. The 3D slip branch is
``common.cone_slip3`` (shared with Chatterjee & Ruina).

``MODE_NO_SOLUTION`` (``P_out`` zeroed) when ``W_NN + W_NT . r <= 0`` (the clamped ratio
would need a negative normal impulse), when ``W`` is not positive definite, or when the
result is not finite. With this direction rule and SPD ``W`` the first cannot happen:
``W_NN + W_NT . rho`` is linear in ``rho``, positive at 0 and (if ``P*_N > 0``) at ``r0``,
so at ``r`` on the segment; if ``P*_N < 0`` it is negative at ``r0`` hence larger than
``W_NN`` on the opposite side, where ``r`` lies; if ``P*_N = 0``, ``W_NT . P*_T = a >= 0``.
(With the literal ``r = mu r0 / |r0|`` it would fail whenever ``P*_N < 0`` under
Painleve-type coupling.) It remains as a guard against rounding and bad input.
Negative ``e`` is perforation: ``v_fN = -e v_N`` keeps the sign of ``v_N``; ``e = -1`` gives
``P_N = 0``. ``mu == 0`` takes the frictionless path ``P = (a / W_NN, 0)`` (``MODE_SLIP``).

Scalar twins ``brach_2d_scalar(vn, vt, wnn, wnt, wtt, e, mu, et) -> (mode, P_N, P_T)`` and
``brach_3d_scalar(vn, v1, v2, wnn, w1, w2, t11, t12, t22, e, mu, et) -> (mode, P_N, P_T1,
P_T2)`` (upper triangle of ``W``) are what batch loops should call: no array views, so
no reference counting in the loop.
"""
import math

from numba import njit

from .cache_guard import guard

# flush stale compiled code before the kernel modules below are imported (cache_guard)
guard(__name__, __file__)

from .common import (
    MODE_NO_SOLUTION,
    MODE_SEPARATING,
    MODE_SLIP,
    MODE_STICK,
    P_E,
    P_ET,
    P_MU,
    cone_slip3,
    det2k,
    finite3,
    spd3_solve,
    store3,
)


@njit(cache=True, error_model="numpy")
def brach_2d_scalar(vn, vt, wnn, wnt, wtt, e, mu, et):
    """Scalar twin of ``brach_2d``: returns ``(mode, P_N, P_T)``; failures return zeros."""
    if vn >= 0.0:
        return MODE_SEPARATING, 0.0, 0.0
    a = -(1.0 + e) * vn
    if mu == 0.0:
        pn = a / wnn
        if wnn > 0.0 and pn - pn == 0.0:
            return MODE_SLIP, pn, 0.0
        return MODE_NO_SOLUTION, 0.0, 0.0
    det = det2k(wnn, wtt, wnt, wnt)        # within 2 ulps: its sign is exact
    if not (det > 0.0 and wnn > 0.0):
        return MODE_NO_SOLUTION, 0.0, 0.0
    # target W P* = (a, b), b = -(1 + e_t) v_T, by Cramer's rule with Kahan's FMA
    # determinants (each within 2 ulps: P* to a few ulps componentwise, backward stable);
    # the cone test is made on the numerators det P*_N, det P*_T (det > 0): no division
    b = -(1.0 + et) * vt
    nn = det2k(a, wtt, wnt, b)
    nt = det2k(wnn, b, wnt, a)
    if nn >= 0.0 and abs(nt) <= mu * nn:
        mode = MODE_STICK
        pn = nn / det
        pt = nt / det
    else:
        if nt > 0.0:
            r = mu
        elif nt < 0.0:
            r = -mu
        elif nt == 0.0:
            r = 0.0
        else:                              # NaN input
            return MODE_NO_SOLUTION, 0.0, 0.0
        den = wnn + wnt * r
        if not (den > 0.0):
            return MODE_NO_SOLUTION, 0.0, 0.0
        pn = a / den
        pt = r * pn
        mode = MODE_SLIP
    if pn - pn == 0.0 and pt - pt == 0.0:
        return mode, pn, pt
    return MODE_NO_SOLUTION, 0.0, 0.0


@njit(cache=True, error_model="numpy")
def brach_2d(v, W, params, P_out):
    """Brach's law, 2D contact: ``mode = brach_2d(v, W, params, P_out)``.

    ``v`` (2,) m/s, ``W`` (2, 2) 1/kg, ``params`` with P_E, P_MU, P_ET; writes the impulse
    on A (N s) into ``P_out`` (2,). See the module docstring."""
    mode, pn, pt = brach_2d_scalar(v[0], v[1], W[0, 0], W[0, 1], W[1, 1],
                                 params[P_E], params[P_MU], params[P_ET])
    P_out[0] = pn
    P_out[1] = pt
    return mode


@njit(cache=True, error_model="numpy")
def brach_3d_scalar(vn, v1, v2, wnn, w1, w2, t11, t12, t22, e, mu, et):
    """Scalar twin of ``brach_3d``: returns ``(mode, P_N, P_T1, P_T2)``; failures return zeros.

    ``W`` is given by its upper triangle ``W[0,0], W[0,1], W[0,2], W[1,1], W[1,2], W[2,2]``."""
    if vn >= 0.0:
        return MODE_SEPARATING, 0.0, 0.0, 0.0
    a = -(1.0 + e) * vn
    if mu == 0.0:
        pn = a / wnn
        if wnn > 0.0 and pn - pn == 0.0:
            return MODE_SLIP, pn, 0.0, 0.0
        return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
    k = -(1.0 + et)
    # positive-definiteness test and target W P* = (a, k v_T1, k v_T2), both compensated
    # (common.spd3_solve): P* to a few ulps, SPD decided exactly
    spd, p0, p1, p2 = spd3_solve(wnn, w1, w2, t11, t12, t22, a, k * v1, k * v2)
    if not spd:
        return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
    if p0 >= 0.0 and math.sqrt(p1 * p1 + p2 * p2) <= mu * p0:
        return finite3(MODE_STICK, p0, p1, p2)
    # clamp the ratio on the cone along P*_T (r = 0 if P*_T = 0)
    return cone_slip3(a, mu, wnn, w1, w2, p1, p2)


@njit(cache=True, error_model="numpy")
def brach_3d(v, W, params, P_out):
    """Brach's law, 3D contact: ``mode = brach_3d(v, W, params, P_out)``.

    ``v`` (3,) m/s, ``W`` (3, 3) symmetric 1/kg (upper triangle read), ``params`` with
    P_E, P_MU, P_ET; writes the impulse on A (N s) into ``P_out`` (3,)."""
    mode, p0, p1, p2 = brach_3d_scalar(
        v[0], v[1], v[2], W[0, 0], W[0, 1], W[0, 2], W[1, 1], W[1, 2], W[2, 2],
        params[P_E], params[P_MU], params[P_ET])
    return store3(P_out, mode, p0, p1, p2)


@njit(cache=True, error_model="numpy")
def brach(v, W, params, P_out):
    """Brach's law, dispatching on the dimension ``v.shape[0]`` (2 or 3)."""
    if v.shape[0] == 2:
        return brach_2d(v, W, params, P_out)
    return brach_3d(v, W, params, P_out)
