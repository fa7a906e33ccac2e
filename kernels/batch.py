"""Batched law evaluation: one parallel loop over contacts, no Python in the loop.

``params`` has shape (1, N_PARAMS) (the same parameters for every contact) or
(n, N_PARAMS) (one row per contact). Outputs are preallocated by the caller:
``P_out`` and ``vf_out`` (n, d), ``dE_out`` (n,), ``mode_out`` (n,) int64.
``dE = P . (v + v_f) / 2`` is the exact kinetic energy change (J).
The loop reads scalars and calls the laws' scalar cores (``dispatch.resolve_*_scalar``),
so no array view, and no reference counting, is made per contact.
"""
import numpy as np
from numba import njit, prange

from .common import P_E, P_ET, P_MU, P_REST, P_TOL
from .dispatch import resolve_2d_scalar, resolve_3d_scalar


@njit(cache=True, parallel=True, error_model="numpy")
def batch_2d(law_id, v, W, params, P_out, vf_out, dE_out, mode_out):
    """Resolve n 2D contacts with law ``law_id`` (see module docstring)."""
    n = v.shape[0]
    last = params.shape[0] - 1  # 0: one shared row; n - 1: a row per contact
    for i in prange(n):
        row = min(np.int64(i), last)  # prange indices are unsigned
        vn = v[i, 0]
        vt = v[i, 1]
        wnn = W[i, 0, 0]
        wnt = W[i, 0, 1]
        wtt = W[i, 1, 1]
        mode, p0, p1 = resolve_2d_scalar(law_id, vn, vt, wnn, wnt, wtt, params[row, P_E],
                                         params[row, P_MU], params[row, P_ET],
                                         params[row, P_REST], params[row, P_TOL])
        f0 = vn + wnn * p0 + wnt * p1
        f1 = vt + wnt * p0 + wtt * p1
        mode_out[i] = mode
        P_out[i, 0] = p0
        P_out[i, 1] = p1
        vf_out[i, 0] = f0
        vf_out[i, 1] = f1
        dE_out[i] = 0.5 * (p0 * (vn + f0) + p1 * (vt + f1))


@njit(cache=True, parallel=True, error_model="numpy")
def batch_3d(law_id, v, W, params, P_out, vf_out, dE_out, mode_out):
    """Resolve n 3D contacts with law ``law_id`` (see module docstring)."""
    n = v.shape[0]
    last = params.shape[0] - 1
    for i in prange(n):
        row = min(np.int64(i), last)
        mode, p0, p1, p2 = resolve_3d_scalar(
            law_id, v[i, 0], v[i, 1], v[i, 2], W[i, 0, 0], W[i, 0, 1], W[i, 0, 2],
            W[i, 1, 1], W[i, 1, 2], W[i, 2, 2], params[row, P_E], params[row, P_MU],
            params[row, P_ET], params[row, P_REST], params[row, P_TOL])
        mode_out[i] = mode
        P_out[i, 0] = p0
        P_out[i, 1] = p1
        P_out[i, 2] = p2
        dE = 0.0
        for a in range(3):
            f = v[i, a] + W[i, a, 0] * p0 + W[i, a, 1] * p1 + W[i, a, 2] * p2
            vf_out[i, a] = f
            dE += P_out[i, a] * (v[i, a] + f)
        dE_out[i] = 0.5 * dE
