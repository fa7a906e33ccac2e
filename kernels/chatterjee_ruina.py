"""Chatterjee & Ruina's two-parameter collision law with Coulomb friction
(A. Chatterjee and A. Ruina, "A new algebraic rigid-body collision law based on impulse
space considerations", J. Appl. Mech. 65:939-951, 1998).

Contact-space conventions (DESIGN §3): normal first ``v = (v_N, v_T[, v_T2])`` (m/s),
``W`` the Delassus matrix (1/kg), ``P`` the impulse on body A (N s), ``v_f = v + W P``.
Parameters read from ``params``: ``P_E`` (e in [0, 1]), ``P_MU`` (mu >= 0),
``P_ET`` (e_t in [-1, 1]).

Equations (DESIGN §4):

* ``P_I = (-v_N / W_NN) n``: plastic frictionless impulse;
* ``P_II = -W^-1 v``: plastic sticking impulse; ``D = P_II - P_I``. Computed here as
  ``D = -W^-1 (0, v_T^I)`` with ``v_T^I = v_T + W_TN P_I,N`` (the tangential velocity after
  ``P_I``), which is the same vector without the cancellation of ``P_II - P_I``. 2D:
  ``D = (v_T^I / det W) (W_NT, -W_NN)`` with ``det W`` and ``W_NN v_T^I = W_NN v_T - W_NT
  v_N`` by Kahan's FMA algorithm (exact direction, magnitude to a few ulps; one division
  per contact); 3D: ``common.spd3_solve`` (exact SPD test up to
  cond ~1e15, forward accurate to a few ulps up to cond ~1e14). The energy identity below
  holds to round-off only if ``D`` is forward accurate: a merely backward-stable ``D``
  creates energy ~``eps cond(W)`` at ``e = e_t = 1``;
* candidate ``P^ = (1 + e) P_I + (1 + e_t) D``; if ``|P^_T| <= mu P^_N`` it is taken
  (``MODE_STICK``: the law's target reached without the cone limiting it);
* else ``P = (1 + e) P_I + k D`` with ``k = mu (1 + e) P_I,N / (|D_T| - mu D_N)``, the point
  where the segment from ``(1 + e) P_I`` towards ``P^`` leaves the cone (``MODE_SLIP``).
  Evaluated as ``P_T = mu P_N D_T / |D_T|``, ``P_N = (1 + e)(-v_N) / (W_NN + W_NT . r)``,
  ``r = P_T / P_N`` (the same point, since ``W_NN D_N + W_NT . D_T = 0``; in 3D
  ``common.cone_slip3``, the tail shared with Brach).

``W D`` has no normal component, so ``v_fN = -e v_N`` in both branches, and the law never
creates kinetic energy for e in [0, 1], e_t in [-1, 1]. In the slip branch the
denominator ``|D_T| - mu D_N`` (equivalently ``W_NN + W_NT . r``) is positive in exact
arithmetic (``(1 + e) P_I`` is inside the cone and ``P^`` outside, so the cone function
grows along ``D``); ``MODE_NO_SOLUTION`` (``P_out``
zeroed) only guards that by rounding, a ``W`` that is not positive definite, or a
non-finite result. ``mu == 0`` takes the frictionless path ``P = ((1 + e) P_I,N, 0)``
(``MODE_SLIP``).

Scalar twins ``chatterjee_ruina_2d_scalar(vn, vt, wnn, wnt, wtt, e, mu, et) -> (mode, P_N,
P_T)`` and ``chatterjee_ruina_3d_scalar(vn, v1, v2, wnn, w1, w2, t11, t12, t22, e, mu, et)
-> (mode, P_N, P_T1, P_T2)`` (upper triangle of ``W``) are what batch loops should call:
no array views, so no reference counting in the loop.
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
def chatterjee_ruina_2d_scalar(vn, vt, wnn, wnt, wtt, e, mu, et):
    """Scalar twin of ``chatterjee_ruina_2d``: returns ``(mode, P_N, P_T)``; failures zeros."""
    if vn >= 0.0:
        return MODE_SEPARATING, 0.0, 0.0
    if mu == 0.0:
        base = (1.0 + e) * (-vn / wnn)   # (1 + e) P_I,N
        if wnn > 0.0 and base - base == 0.0:
            return MODE_SLIP, base, 0.0
        return MODE_NO_SOLUTION, 0.0, 0.0
    det = det2k(wnn, wtt, wnt, wnt)        # within 2 ulps: its sign is exact
    if not (det > 0.0 and wnn > 0.0):
        return MODE_NO_SOLUTION, 0.0, 0.0
    # D = -W^-1 (0, v_T^I) = (v_T^I / det) (W_NT, -W_NN): its direction is exact, and
    # m = W_NN v_T^I = W_NN v_T - W_NT v_N (Kahan, 2 ulps) and det give its size to a few
    # ulps (so W D = (0, -v_T^I) and the energy identity hold to round-off). Scaled by
    # W_NN det > 0: P^ = (a det + k W_NT m, -k W_NN m) / (W_NN det), a = (1 + e)(-v_N);
    # the cone test is made before the one division.
    a = -(1.0 + e) * vn
    m = det2k(vt, wnn, wnt, vn)
    k = 1.0 + et
    nn = a * det + k * wnt * m
    nt = -k * wnn * m
    if abs(nt) <= mu * nn:
        mode = MODE_STICK
        q = 1.0 / (wnn * det)
        pn = nn * q
        pt = nt * q
    else:
        # on the cone along D_T: P_T = r P_N, r = -mu sign(m), P_N = a / (W_NN + W_NT r)
        # (the same point as (1 + e) P_I + k D with k = mu (1 + e) P_I,N / (|D_T| - mu D_N));
        # branch-free (m = 0 always sticks); the 0 m term makes den NaN for a NaN m
        r = math.copysign(mu, -m)
        den = wnn + wnt * r + 0.0 * m
        if not (den > 0.0):
            return MODE_NO_SOLUTION, 0.0, 0.0
        pn = a / den
        pt = r * pn
        mode = MODE_SLIP
    if pn - pn == 0.0 and pt - pt == 0.0:
        return mode, pn, pt
    return MODE_NO_SOLUTION, 0.0, 0.0


@njit(cache=True, error_model="numpy")
def chatterjee_ruina_2d(v, W, params, P_out):
    """Chatterjee & Ruina's law, 2D contact: ``mode = chatterjee_ruina_2d(v, W, params, P_out)``.

    ``v`` (2,) m/s, ``W`` (2, 2) 1/kg, ``params`` with P_E, P_MU, P_ET; writes the impulse
    on A (N s) into ``P_out`` (2,). See the module docstring."""
    mode, pn, pt = chatterjee_ruina_2d_scalar(v[0], v[1], W[0, 0], W[0, 1], W[1, 1],
                                            params[P_E], params[P_MU], params[P_ET])
    P_out[0] = pn
    P_out[1] = pt
    return mode


@njit(cache=True, error_model="numpy")
def chatterjee_ruina_3d_scalar(vn, v1, v2, wnn, w1, w2, t11, t12, t22, e, mu, et):
    """Scalar twin of ``chatterjee_ruina_3d``: returns ``(mode, P_N, P_T1, P_T2)``.

    ``W`` is given by its upper triangle ``W[0,0], W[0,1], W[0,2], W[1,1], W[1,2], W[2,2]``.
    Failures return zeros."""
    if vn >= 0.0:
        return MODE_SEPARATING, 0.0, 0.0, 0.0
    pi = -vn / wnn
    base = (1.0 + e) * pi
    if mu == 0.0:
        if wnn > 0.0 and base - base == 0.0:
            return MODE_SLIP, base, 0.0, 0.0
        return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
    # positive-definiteness test and D = -W^-1 (0, v_T^I), both compensated
    # (common.spd3_solve): D to a few ulps, SPD decided exactly
    spd, d0, d1, d2 = spd3_solve(wnn, w1, w2, t11, t12, t22, 0.0, -(v1 + w1 * pi),
                                 -(v2 + w2 * pi))
    if not spd:
        return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
    k = 1.0 + et
    p0 = base + k * d0
    p1 = k * d1
    p2 = k * d2
    if math.sqrt(p1 * p1 + p2 * p2) <= mu * p0:
        return finite3(MODE_STICK, p0, p1, p2)
    # on the cone along D_T: the point (1 + e) P_I + k D with k = mu (1 + e) P_I,N /
    # (|D_T| - mu D_N) is P_T = mu P_N D_T / |D_T|, P_N = (1 + e) (-v_N) / (W_NN + W_NT . r)
    # (W D has no normal component)
    return cone_slip3(-(1.0 + e) * vn, mu, wnn, w1, w2, d1, d2)


@njit(cache=True, error_model="numpy")
def chatterjee_ruina_3d(v, W, params, P_out):
    """Chatterjee & Ruina's law, 3D contact: ``mode = chatterjee_ruina_3d(v, W, params, P_out)``.

    ``v`` (3,) m/s, ``W`` (3, 3) symmetric 1/kg (upper triangle read), ``params`` with
    P_E, P_MU, P_ET; writes the impulse on A (N s) into ``P_out`` (3,)."""
    mode, p0, p1, p2 = chatterjee_ruina_3d_scalar(
        v[0], v[1], v[2], W[0, 0], W[0, 1], W[0, 2], W[1, 1], W[1, 2], W[2, 2],
        params[P_E], params[P_MU], params[P_ET])
    return store3(P_out, mode, p0, p1, p2)


@njit(cache=True, error_model="numpy")
def chatterjee_ruina(v, W, params, P_out):
    """Chatterjee & Ruina's law, dispatching on the dimension ``v.shape[0]`` (2 or 3)."""
    if v.shape[0] == 2:
        return chatterjee_ruina_2d(v, W, params, P_out)
    return chatterjee_ruina_3d(v, W, params, P_out)
