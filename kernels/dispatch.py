"""Law dispatch by integer id, for compiled callers that hold a per-contact law table.

``resolve_2d`` references only the 2D kernels and ``resolve_3d`` only the 3D ones, so a
2D caller never compiles 3D code. Law ids are the ``LAW_*`` constants of ``common``.

The ``*_scalar`` forms take and return scalars (``W`` by its upper triangle, normal
first) and call each law's scalar core: a caller's loop then passes no array views and
pays no reference counting per contact (the batch kernels use them).
"""
from numba import njit

from .cache_guard import guard

# flush stale compiled callers before any kernel module below is imported (cache_guard)
guard(__name__, __file__)

from .brach import brach_2d, brach_2d_scalar, brach_3d, brach_3d_scalar
from .chatterjee_ruina import (chatterjee_ruina_2d, chatterjee_ruina_2d_scalar,
                               chatterjee_ruina_3d, chatterjee_ruina_3d_scalar)
from .common import (LAW_BRACH, LAW_CHATTERJEE_RUINA, LAW_KANE_LEVINSON, LAW_ROUTH,
                     LAW_SMITH, MODE_NO_SOLUTION, P_E, P_ET, P_MU, P_REST, P_TOL)
from .kane_levinson import (kane_levinson_2d, kane_levinson_2d_scalar, kane_levinson_3d,
                            kane_levinson_3d_scalar)
from .routh import routh_2d, routh_2d_scalar, routh_3d, routh_3d_scalar
from .smith import smith_2d, smith_2d_scalar, smith_3d, smith_3d_scalar


@njit(cache=True, error_model="numpy")
def resolve_2d_scalar(law_id, vn, vt, wnn, wnt, wtt, e, mu, et, rest, tol):
    """Law ``law_id`` on a 2D contact given by scalars; returns ``(mode, P_N, P_T)``.
    ``tol`` is unused in 2D (Routh 2D is exact)."""
    if law_id == LAW_KANE_LEVINSON:
        return kane_levinson_2d_scalar(vn, vt, wnn, wnt, wtt, e, mu)
    if law_id == LAW_BRACH:
        return brach_2d_scalar(vn, vt, wnn, wnt, wtt, e, mu, et)
    if law_id == LAW_CHATTERJEE_RUINA:
        return chatterjee_ruina_2d_scalar(vn, vt, wnn, wnt, wtt, e, mu, et)
    if law_id == LAW_ROUTH:
        return routh_2d_scalar(vn, vt, wnn, wnt, wtt, e, mu, rest)
    if law_id == LAW_SMITH:
        return smith_2d_scalar(vn, vt, wnn, wnt, wtt, e, mu)
    return MODE_NO_SOLUTION, 0.0, 0.0


@njit(cache=True, error_model="numpy")
def resolve_3d_scalar(law_id, vn, v1, v2, wnn, w1, w2, t11, t12, t22, e, mu, et, rest, tol):
    """Law ``law_id`` on a 3D contact given by scalars (``W`` by its upper triangle
    ``W_NN, W_NT1, W_NT2, W_T1T1, W_T1T2, W_T2T2``); returns ``(mode, P_N, P_T1, P_T2)``."""
    if law_id == LAW_KANE_LEVINSON:
        return kane_levinson_3d_scalar(vn, v1, v2, wnn, w1, w2, t11, t12, t22, e, mu)
    if law_id == LAW_BRACH:
        return brach_3d_scalar(vn, v1, v2, wnn, w1, w2, t11, t12, t22, e, mu, et)
    if law_id == LAW_CHATTERJEE_RUINA:
        return chatterjee_ruina_3d_scalar(vn, v1, v2, wnn, w1, w2, t11, t12, t22, e, mu, et)
    if law_id == LAW_ROUTH:
        return routh_3d_scalar(vn, v1, v2, wnn, w1, w2, t11, t12, t22, e, mu, rest, tol)
    if law_id == LAW_SMITH:
        return smith_3d_scalar(vn, v1, v2, wnn, w1, w2, t11, t12, t22, e, mu)
    return MODE_NO_SOLUTION, 0.0, 0.0, 0.0


@njit(cache=True, error_model="numpy")
def resolve_2d(law_id, v, W, params, P_out):
    """Apply law ``law_id`` to a 2D contact; same contract as every law kernel."""
    mode, pn, pt = resolve_2d_scalar(law_id, v[0], v[1], W[0, 0], W[0, 1], W[1, 1],
                                     params[P_E], params[P_MU], params[P_ET],
                                     params[P_REST], params[P_TOL])
    P_out[0] = pn
    P_out[1] = pt
    return mode


@njit(cache=True, error_model="numpy")
def resolve_3d(law_id, v, W, params, P_out):
    """Apply law ``law_id`` to a 3D contact; same contract as every law kernel."""
    mode, pn, p1, p2 = resolve_3d_scalar(law_id, v[0], v[1], v[2], W[0, 0], W[0, 1], W[0, 2],
                                         W[1, 1], W[1, 2], W[2, 2], params[P_E],
                                         params[P_MU], params[P_ET], params[P_REST],
                                         params[P_TOL])
    P_out[0] = pn
    P_out[1] = p1
    P_out[2] = p2
    return mode


# Routh's 2D scalar core compiled as a function of its own, for the stepper (issue 14):
# ``routh.routh_2d`` inlines it (``inline='always'``, for the batch kernels), and Numba
# copies an inlined body block by block, each time with its whole variable scope: 1.4-1.8 s
# of the first run of a Routh scene for this 133-block core. Called, it is typed and
# lowered once. The same function and flags: the same numbers.
_routh_2d_core = njit(cache=True, error_model="numpy")(routh_2d_scalar.py_func)


@njit(cache=True, error_model="numpy")
def _routh_2d_called(v, W, params, P_out):
    """``routh.routh_2d`` with its scalar core called (``_routh_2d_core``), not inlined."""
    mode, P0, P1 = _routh_2d_core(v[0], v[1], W[0, 0], W[0, 1], W[1, 1], params[P_E],
                                  params[P_MU], params[P_REST])
    P_out[0] = P0
    P_out[1] = P1
    return mode


LAW_ANY = -1
"""``law`` of the ``*_as`` forms for a caller with several laws: dispatch per contact on
``law_id`` (every law compiled)."""


@njit(cache=True, error_model="numpy", inline="always")
def resolve_2d_as(law, law_id, v, W, params, P_out):
    """``resolve_2d`` with the law fixed at compile time: ``law`` is a constant ``LAW_*``
    closed over by the (inlining) caller, so the other laws are pruned before typing and
    never compiled (issue 14), or ``LAW_ANY``: dispatch on ``law_id``. The law's own array
    kernel is called (compiled once, not inlined into a large caller; Routh's with its
    scalar core called, ``_routh_2d_called``)."""
    if law == LAW_KANE_LEVINSON:
        return kane_levinson_2d(v, W, params, P_out)
    if law == LAW_BRACH:
        return brach_2d(v, W, params, P_out)
    if law == LAW_CHATTERJEE_RUINA:
        return chatterjee_ruina_2d(v, W, params, P_out)
    if law == LAW_ROUTH:
        return _routh_2d_called(v, W, params, P_out)
    if law == LAW_SMITH:
        return smith_2d(v, W, params, P_out)
    return resolve_2d(law_id, v, W, params, P_out)


@njit(cache=True, error_model="numpy", inline="always")
def resolve_3d_as(law, law_id, v, W, params, P_out):
    """``resolve_3d`` with the law fixed at compile time (see ``resolve_2d_as``)."""
    if law == LAW_KANE_LEVINSON:
        return kane_levinson_3d(v, W, params, P_out)
    if law == LAW_BRACH:
        return brach_3d(v, W, params, P_out)
    if law == LAW_CHATTERJEE_RUINA:
        return chatterjee_ruina_3d(v, W, params, P_out)
    if law == LAW_ROUTH:
        return routh_3d(v, W, params, P_out)
    if law == LAW_SMITH:
        return smith_3d(v, W, params, P_out)
    return resolve_3d(law_id, v, W, params, P_out)
