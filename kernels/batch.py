"""Batched law evaluation: one parallel loop over contacts, no Python in the loop.

``params`` has shape (1, N_PARAMS) (the same parameters for every contact) or
(n, N_PARAMS) (one row per contact). Outputs are preallocated by the caller:
``P_out`` and ``vf_out`` (n, d), ``dE_out`` (n,), ``mode_out`` (n,) int64.
``dE = P . (v + v_f) / 2`` is the exact kinetic energy change (J).
"""
import numpy as np
from numba import njit, prange

from .dispatch import resolve_2d, resolve_3d


@njit(cache=True, parallel=True)
def batch_2d(law_id, v, W, params, P_out, vf_out, dE_out, mode_out):
    """Resolve n 2D contacts with law ``law_id`` (see module docstring)."""
    n = v.shape[0]
    last = params.shape[0] - 1  # 0: one shared row; n - 1: a row per contact
    for i in prange(n):
        row = min(np.int64(i), last)  # prange indices are unsigned
        mode_out[i] = resolve_2d(law_id, v[i], W[i], params[row], P_out[i])
        p0 = P_out[i, 0]
        p1 = P_out[i, 1]
        f0 = v[i, 0] + W[i, 0, 0] * p0 + W[i, 0, 1] * p1
        f1 = v[i, 1] + W[i, 1, 0] * p0 + W[i, 1, 1] * p1
        vf_out[i, 0] = f0
        vf_out[i, 1] = f1
        dE_out[i] = 0.5 * (p0 * (v[i, 0] + f0) + p1 * (v[i, 1] + f1))


@njit(cache=True, parallel=True)
def batch_3d(law_id, v, W, params, P_out, vf_out, dE_out, mode_out):
    """Resolve n 3D contacts with law ``law_id`` (see module docstring)."""
    n = v.shape[0]
    last = params.shape[0] - 1  # 0: one shared row; n - 1: a row per contact
    for i in prange(n):
        row = min(np.int64(i), last)  # prange indices are unsigned
        mode_out[i] = resolve_3d(law_id, v[i], W[i], params[row], P_out[i])
        dE = 0.0
        for a in range(3):
            f = v[i, a]
            for b in range(3):
                f += W[i, a, b] * P_out[i, b]
            vf_out[i, a] = f
            dE += P_out[i, a] * (v[i, a] + f)
        dE_out[i] = 0.5 * dE
