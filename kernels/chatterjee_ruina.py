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
  ``P_I``), which is the same vector without the cancellation of ``P_II - P_I``;
* candidate ``P^ = (1 + e) P_I + (1 + e_t) D``; if ``|P^_T| <= mu P^_N`` it is taken
  (``MODE_STICK``: the law's target reached without the cone limiting it);
* else ``P = (1 + e) P_I + k D`` with ``k = mu (1 + e) P_I,N / (|D_T| - mu D_N)``, the point
  where the segment from ``(1 + e) P_I`` towards ``P^`` leaves the cone (``MODE_SLIP``).

``W D`` has no normal component, so ``v_fN = -e v_N`` in both branches, and the law never
creates kinetic energy for e in [0, 1], e_t in [-1, 1]. In the slip branch the
denominator is positive in exact arithmetic (``(1 + e) P_I`` is inside the cone and
``P^`` outside, so the cone function grows along ``D``); ``MODE_NO_SOLUTION`` (``P_out``
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

from .common import (
    MODE_NO_SOLUTION,
    MODE_SEPARATING,
    MODE_SLIP,
    MODE_STICK,
    P_E,
    P_ET,
    P_MU,
    det3s,
    solve2,
    solve3s,
)


@njit(cache=True, error_model="numpy")
def chatterjee_ruina_2d_scalar(vn, vt, wnn, wnt, wtt, e, mu, et):
    """Scalar twin of ``chatterjee_ruina_2d``: returns ``(mode, P_N, P_T)``; failures zeros."""
    if vn >= 0.0:
        return MODE_SEPARATING, 0.0, 0.0
    pi = -vn / wnn                       # P_I,N
    base = (1.0 + e) * pi                # (1 + e) P_I,N
    if mu == 0.0:
        if wnn > 0.0 and base - base == 0.0:
            return MODE_SLIP, base, 0.0
        return MODE_NO_SOLUTION, 0.0, 0.0
    det = wnn * wtt - wnt * wnt
    if not (det > 0.0 and wnn > 0.0):
        return MODE_NO_SOLUTION, 0.0, 0.0
    # D = -W^-1 (0, v_T^I), v_T^I = v_T + W_TN P_I,N
    d0, d1 = solve2(wnn, wnt, wtt, 0.0, -(vt + wnt * pi))
    k = 1.0 + et
    pn = base + k * d0
    pt = k * d1
    if abs(pt) <= mu * pn:
        mode = MODE_STICK
    else:
        den = abs(d1) - mu * d0
        if not (den > 0.0):
            return MODE_NO_SOLUTION, 0.0, 0.0
        k = mu * base / den
        pn = base + k * d0
        pt = k * d1
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
    if not (det3s(wnn, w1, w2, t11, t12, t22) > 0.0 and wnn > 0.0):
        return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
    d0, d1, d2 = solve3s(wnn, w1, w2, t11, t12, t22, 0.0, -(v1 + w1 * pi), -(v2 + w2 * pi))
    k = 1.0 + et
    p0 = base + k * d0
    p1 = k * d1
    p2 = k * d2
    if math.sqrt(p1 * p1 + p2 * p2) <= mu * p0:
        mode = MODE_STICK
    else:
        den = math.sqrt(d1 * d1 + d2 * d2) - mu * d0
        if not (den > 0.0):
            return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
        k = mu * base / den
        p0 = base + k * d0
        p1 = k * d1
        p2 = k * d2
        mode = MODE_SLIP
    if p0 - p0 == 0.0 and p1 - p1 == 0.0 and p2 - p2 == 0.0:
        return mode, p0, p1, p2
    return MODE_NO_SOLUTION, 0.0, 0.0, 0.0


@njit(cache=True, error_model="numpy")
def chatterjee_ruina_3d(v, W, params, P_out):
    """Chatterjee & Ruina's law, 3D contact: ``mode = chatterjee_ruina_3d(v, W, params, P_out)``.

    ``v`` (3,) m/s, ``W`` (3, 3) symmetric 1/kg (upper triangle read), ``params`` with
    P_E, P_MU, P_ET; writes the impulse on A (N s) into ``P_out`` (3,)."""
    mode, p0, p1, p2 = chatterjee_ruina_3d_scalar(
        v[0], v[1], v[2], W[0, 0], W[0, 1], W[0, 2], W[1, 1], W[1, 2], W[2, 2],
        params[P_E], params[P_MU], params[P_ET])
    P_out[0] = p0
    P_out[1] = p1
    P_out[2] = p2
    return mode


@njit(cache=True, error_model="numpy")
def chatterjee_ruina(v, W, params, P_out):
    """Chatterjee & Ruina's law, dispatching on the dimension ``v.shape[0]`` (2 or 3)."""
    if v.shape[0] == 2:
        return chatterjee_ruina_2d(v, W, params, P_out)
    return chatterjee_ruina_3d(v, W, params, P_out)
