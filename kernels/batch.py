"""Batched law evaluation: one parallel loop over contacts, no Python in the loop.

``params`` has shape (1, N_PARAMS) (the same parameters for every contact) or
(n, N_PARAMS) (one row per contact; a shorter table repeats its last row). Outputs are
preallocated by the caller: ``P_out`` and ``vf_out`` (n, d), ``dE_out`` (n,), ``mode_out`` (n,) int64.
``dE = P . (v + v_f) / 2`` is the exact kinetic energy change (J).

The loops read scalars and call the laws' scalar cores, so no array view, and no
reference counting, is made per contact. With shared parameters (the common case) the
law switch and the parameter reads are hoisted out of the loop: there is one loop per
law, calling that law's core directly (its code inlined into the loop). Per-row
parameters go through ``dispatch.resolve_*_scalar`` in a single generic loop.
An unknown ``law_id`` gives ``MODE_NO_SOLUTION`` with ``P = 0`` for every contact.
"""
import numpy as np
from numba import njit, prange

from .cache_guard import guard

# flush stale compiled callers before any kernel module below is imported (cache_guard):
# the loops here have the law cores inlined
guard(__name__, __file__)

from .brach import brach_2d_scalar, brach_3d_scalar
from .chatterjee_ruina import chatterjee_ruina_2d_scalar, chatterjee_ruina_3d_scalar
from .common import (LAW_BRACH, LAW_CHATTERJEE_RUINA, LAW_KANE_LEVINSON, LAW_ROUTH,
                     LAW_SMITH, MODE_NO_SOLUTION, P_E, P_ET, P_MU, P_REST, P_TOL)
from .dispatch import resolve_2d_scalar, resolve_3d_scalar
from .kane_levinson import kane_levinson_2d_scalar, kane_levinson_3d_scalar
from .routh import routh_2d_scalar, routh_3d_scalar
from .smith import smith_2d_scalar, smith_3d_scalar


@njit(cache=True, inline="always", error_model="numpy")
def _store_2d(i, mode, p0, p1, vn, vt, wnn, wnt, wtt, P_out, vf_out, dE_out, mode_out):
    """Write contact ``i``'s outcome: P, v_f = v + W P, dE = P . (v + v_f) / 2, mode."""
    f0 = vn + wnn * p0 + wnt * p1
    f1 = vt + wnt * p0 + wtt * p1
    mode_out[i] = mode
    P_out[i, 0] = p0
    P_out[i, 1] = p1
    vf_out[i, 0] = f0
    vf_out[i, 1] = f1
    dE_out[i] = 0.5 * (p0 * (vn + f0) + p1 * (vt + f1))


@njit(cache=True, inline="always", error_model="numpy")
def _store_3d(i, mode, p0, p1, p2, vn, v1, v2, wnn, w1, w2, t11, t12, t22, P_out, vf_out,
              dE_out, mode_out):
    """Write contact ``i``'s outcome (3D; ``W`` by its upper triangle)."""
    f0 = vn + wnn * p0 + w1 * p1 + w2 * p2
    f1 = v1 + w1 * p0 + t11 * p1 + t12 * p2
    f2 = v2 + w2 * p0 + t12 * p1 + t22 * p2
    mode_out[i] = mode
    P_out[i, 0] = p0
    P_out[i, 1] = p1
    P_out[i, 2] = p2
    vf_out[i, 0] = f0
    vf_out[i, 1] = f1
    vf_out[i, 2] = f2
    dE_out[i] = 0.5 * (p0 * (vn + f0) + p1 * (v1 + f1) + p2 * (v2 + f2))


@njit(cache=True, parallel=True, error_model="numpy")
def batch_2d(law_id, v, W, params, P_out, vf_out, dE_out, mode_out):
    """Resolve n 2D contacts with law ``law_id`` (see module docstring)."""
    n = v.shape[0]
    if params.shape[0] != 1:
        # one parameter row per contact: generic loop through the dispatcher
        last = params.shape[0] - 1
        for i in prange(n):
            r = min(np.int64(i), last)  # prange indices are unsigned
            vn = v[i, 0]
            vt = v[i, 1]
            wnn = W[i, 0, 0]
            wnt = W[i, 0, 1]
            wtt = W[i, 1, 1]
            mode, p0, p1 = resolve_2d_scalar(law_id, vn, vt, wnn, wnt, wtt, params[r, P_E],
                                             params[r, P_MU], params[r, P_ET],
                                             params[r, P_REST], params[r, P_TOL])
            _store_2d(i, mode, p0, p1, vn, vt, wnn, wnt, wtt, P_out, vf_out, dE_out, mode_out)
        return
    e = params[0, P_E]
    mu = params[0, P_MU]
    et = params[0, P_ET]
    rest = params[0, P_REST]
    if law_id == LAW_KANE_LEVINSON:
        for i in prange(n):
            vn = v[i, 0]
            vt = v[i, 1]
            wnn = W[i, 0, 0]
            wnt = W[i, 0, 1]
            wtt = W[i, 1, 1]
            mode, p0, p1 = kane_levinson_2d_scalar(vn, vt, wnn, wnt, wtt, e, mu)
            _store_2d(i, mode, p0, p1, vn, vt, wnn, wnt, wtt, P_out, vf_out, dE_out, mode_out)
    elif law_id == LAW_BRACH:
        for i in prange(n):
            vn = v[i, 0]
            vt = v[i, 1]
            wnn = W[i, 0, 0]
            wnt = W[i, 0, 1]
            wtt = W[i, 1, 1]
            mode, p0, p1 = brach_2d_scalar(vn, vt, wnn, wnt, wtt, e, mu, et)
            _store_2d(i, mode, p0, p1, vn, vt, wnn, wnt, wtt, P_out, vf_out, dE_out, mode_out)
    elif law_id == LAW_CHATTERJEE_RUINA:
        for i in prange(n):
            vn = v[i, 0]
            vt = v[i, 1]
            wnn = W[i, 0, 0]
            wnt = W[i, 0, 1]
            wtt = W[i, 1, 1]
            mode, p0, p1 = chatterjee_ruina_2d_scalar(vn, vt, wnn, wnt, wtt, e, mu, et)
            _store_2d(i, mode, p0, p1, vn, vt, wnn, wnt, wtt, P_out, vf_out, dE_out, mode_out)
    elif law_id == LAW_ROUTH:
        for i in prange(n):
            vn = v[i, 0]
            vt = v[i, 1]
            wnn = W[i, 0, 0]
            wnt = W[i, 0, 1]
            wtt = W[i, 1, 1]
            mode, p0, p1 = routh_2d_scalar(vn, vt, wnn, wnt, wtt, e, mu, rest)
            _store_2d(i, mode, p0, p1, vn, vt, wnn, wnt, wtt, P_out, vf_out, dE_out, mode_out)
    elif law_id == LAW_SMITH:
        for i in prange(n):
            vn = v[i, 0]
            vt = v[i, 1]
            wnn = W[i, 0, 0]
            wnt = W[i, 0, 1]
            wtt = W[i, 1, 1]
            mode, p0, p1 = smith_2d_scalar(vn, vt, wnn, wnt, wtt, e, mu)
            _store_2d(i, mode, p0, p1, vn, vt, wnn, wnt, wtt, P_out, vf_out, dE_out, mode_out)
    else:
        for i in prange(n):
            _store_2d(i, MODE_NO_SOLUTION, 0.0, 0.0, v[i, 0], v[i, 1], 0.0, 0.0, 0.0, P_out,
                      vf_out, dE_out, mode_out)


@njit(cache=True, parallel=True, error_model="numpy")
def batch_3d(law_id, v, W, params, P_out, vf_out, dE_out, mode_out):
    """Resolve n 3D contacts with law ``law_id`` (see module docstring)."""
    n = v.shape[0]
    if params.shape[0] != 1:
        last = params.shape[0] - 1
        for i in prange(n):
            r = min(np.int64(i), last)
            vn = v[i, 0]
            v1 = v[i, 1]
            v2 = v[i, 2]
            wnn = W[i, 0, 0]
            w1 = W[i, 0, 1]
            w2 = W[i, 0, 2]
            t11 = W[i, 1, 1]
            t12 = W[i, 1, 2]
            t22 = W[i, 2, 2]
            mode, p0, p1, p2 = resolve_3d_scalar(
                law_id, vn, v1, v2, wnn, w1, w2, t11, t12, t22, params[r, P_E],
                params[r, P_MU], params[r, P_ET], params[r, P_REST], params[r, P_TOL])
            _store_3d(i, mode, p0, p1, p2, vn, v1, v2, wnn, w1, w2, t11, t12, t22, P_out,
                      vf_out, dE_out, mode_out)
        return
    e = params[0, P_E]
    mu = params[0, P_MU]
    et = params[0, P_ET]
    rest = params[0, P_REST]
    tol = params[0, P_TOL]
    if law_id == LAW_KANE_LEVINSON:
        for i in prange(n):
            vn = v[i, 0]
            v1 = v[i, 1]
            v2 = v[i, 2]
            wnn = W[i, 0, 0]
            w1 = W[i, 0, 1]
            w2 = W[i, 0, 2]
            t11 = W[i, 1, 1]
            t12 = W[i, 1, 2]
            t22 = W[i, 2, 2]
            mode, p0, p1, p2 = kane_levinson_3d_scalar(vn, v1, v2, wnn, w1, w2, t11, t12,
                                                       t22, e, mu)
            _store_3d(i, mode, p0, p1, p2, vn, v1, v2, wnn, w1, w2, t11, t12, t22, P_out,
                      vf_out, dE_out, mode_out)
    elif law_id == LAW_BRACH:
        for i in prange(n):
            vn = v[i, 0]
            v1 = v[i, 1]
            v2 = v[i, 2]
            wnn = W[i, 0, 0]
            w1 = W[i, 0, 1]
            w2 = W[i, 0, 2]
            t11 = W[i, 1, 1]
            t12 = W[i, 1, 2]
            t22 = W[i, 2, 2]
            mode, p0, p1, p2 = brach_3d_scalar(vn, v1, v2, wnn, w1, w2, t11, t12, t22, e,
                                               mu, et)
            _store_3d(i, mode, p0, p1, p2, vn, v1, v2, wnn, w1, w2, t11, t12, t22, P_out,
                      vf_out, dE_out, mode_out)
    elif law_id == LAW_CHATTERJEE_RUINA:
        for i in prange(n):
            vn = v[i, 0]
            v1 = v[i, 1]
            v2 = v[i, 2]
            wnn = W[i, 0, 0]
            w1 = W[i, 0, 1]
            w2 = W[i, 0, 2]
            t11 = W[i, 1, 1]
            t12 = W[i, 1, 2]
            t22 = W[i, 2, 2]
            mode, p0, p1, p2 = chatterjee_ruina_3d_scalar(vn, v1, v2, wnn, w1, w2, t11, t12,
                                                          t22, e, mu, et)
            _store_3d(i, mode, p0, p1, p2, vn, v1, v2, wnn, w1, w2, t11, t12, t22, P_out,
                      vf_out, dE_out, mode_out)
    elif law_id == LAW_ROUTH:
        for i in prange(n):
            vn = v[i, 0]
            v1 = v[i, 1]
            v2 = v[i, 2]
            wnn = W[i, 0, 0]
            w1 = W[i, 0, 1]
            w2 = W[i, 0, 2]
            t11 = W[i, 1, 1]
            t12 = W[i, 1, 2]
            t22 = W[i, 2, 2]
            mode, p0, p1, p2 = routh_3d_scalar(vn, v1, v2, wnn, w1, w2, t11, t12, t22, e, mu,
                                               rest, tol)
            _store_3d(i, mode, p0, p1, p2, vn, v1, v2, wnn, w1, w2, t11, t12, t22, P_out,
                      vf_out, dE_out, mode_out)
    elif law_id == LAW_SMITH:
        for i in prange(n):
            vn = v[i, 0]
            v1 = v[i, 1]
            v2 = v[i, 2]
            wnn = W[i, 0, 0]
            w1 = W[i, 0, 1]
            w2 = W[i, 0, 2]
            t11 = W[i, 1, 1]
            t12 = W[i, 1, 2]
            t22 = W[i, 2, 2]
            mode, p0, p1, p2 = smith_3d_scalar(vn, v1, v2, wnn, w1, w2, t11, t12, t22, e, mu)
            _store_3d(i, mode, p0, p1, p2, vn, v1, v2, wnn, w1, w2, t11, t12, t22, P_out,
                      vf_out, dE_out, mode_out)
    else:
        for i in prange(n):
            _store_3d(i, MODE_NO_SOLUTION, 0.0, 0.0, 0.0, v[i, 0], v[i, 1], v[i, 2], 0.0, 0.0,
                      0.0, 0.0, 0.0, 0.0, P_out, vf_out, dE_out, mode_out)
