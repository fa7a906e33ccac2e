"""Batched law evaluation with fused input validation: one parallel loop over contacts.

Each (law, dimension) has its own compiled entry, ``batch_2d_<law>`` / ``batch_3d_<law>``
(``kernel_for(law_id, d)`` picks it), with the contract::

    nbad, first_bad, nfail, first_fail = entry(v, W, params, lo, hi, check, sym_rtol,
                                               gain_rtol, P_out, vf_out, dE_out,
                                               gain_out, mode_out)

* ``v`` (n, d) m/s, normal first; ``W`` (n, d, d) 1/kg (DESIGN §3).
* ``params`` (1, N_PARAMS) (the same parameters for every contact) or (m, N_PARAMS)
  (one row per contact; a shorter table repeats its last row), layout of ``common``.
* ``lo``, ``hi`` (N_PARAMS,): with ``check``, every parameter row must satisfy
  ``lo <= x <= hi`` and be finite (use -inf/inf for a slot without a range).
* ``check`` (bool): validate every contact in the loop, namely ``v`` and ``W`` finite,
  ``|W_ij - W_ji| <= sym_rtol max|W_kl|`` (then ``W`` is symmetrised as
  ``(W + W^T) / 2``), ``W`` positive definite and the parameter row in range. A contact
  that fails gets the code ``BAD_*`` below in ``mode_out`` and is not resolved.
  Without ``check`` the upper triangle of ``W`` is read as is and nothing is checked.
  Positive definiteness: 2D ``W_NN > 0`` and ``det W > 0`` with ``det W`` by Kahan's FMA
  algorithm (``common.det2k``, within 2 ulps: its sign is exact); 3D the leading minors
  of Sylvester's criterion, i.e. the products of the pivots of ``W = L D L^T`` (``W_NN``,
  the 2x2 minor by ``det2k``, ``det W`` from FMA cofactors), all > 0, division-free.
* Outputs (preallocated): ``P_out``, ``vf_out`` (n, d), ``dE_out`` (n,), ``gain_out``
  (n,) bool, ``mode_out`` (n,) int64. ``v_f = v + W P``; ``dE = P . (v + v_f) / 2`` is the
  exact kinetic energy change (J); ``gain_out`` flags ``dE > gain_rtol * S`` with
  ``S = sum_k |P_k| (|v_k| + |v_f,k|) / 2`` (the round-off scale of ``dE``), i.e. energy
  created beyond round-off. A law failure (negative mode) leaves ``P = 0``, ``v_f = v``.
* Returns the number of contacts refused by validation and the smallest such index
  (``n`` if none), and the same for law failures (negative law modes).

One generic loop per dimension (``_loop_2d``, ``_loop_3d``, inlined, taking the law core
as an argument) and a two-line entry per law: each entry compiles only its law and is
cached on disk (a law passed as an argument to a non-inlined function, or closed over,
compiles but is not cached; an if-chain over a law id compiles every law). Entries need
distinct names: Numba's cache key is the function's qualified name and source file.

The loops read scalars and call the laws' scalar cores (``_core_*`` adapters below, all
with the signature of ``dispatch.resolve_*_scalar`` minus the law id): no array view,
hence no reference counting, per contact.
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
                     LAW_SMITH, N_PARAMS, P_E, P_ET, P_MU, P_REST, P_TOL, det2k)
from .kane_levinson import kane_levinson_2d_scalar, kane_levinson_3d_scalar
from .routh import routh_2d_scalar, routh_3d_scalar
from .smith import smith_2d_scalar, smith_3d_scalar

# ---- validation codes written into mode_out for refused contacts (check=True) ------------
BAD_V = -10        # v has a non-finite component
BAD_W = -11        # W has a non-finite entry
BAD_SYM = -12      # |W - W^T| > sym_rtol max|W|
BAD_SPD = -13      # W is not positive definite
BAD_PARAM = -14    # a parameter of the contact's row is out of range or not finite


# ---- law cores with one signature: (mode, P...) = core(v..., W upper..., e, mu, et, rest, tol)
@njit(cache=True, inline="always", error_model="numpy")
def _core_kl_2d(vn, vt, wnn, wnt, wtt, e, mu, et, rest, tol):
    return kane_levinson_2d_scalar(vn, vt, wnn, wnt, wtt, e, mu)


@njit(cache=True, inline="always", error_model="numpy")
def _core_brach_2d(vn, vt, wnn, wnt, wtt, e, mu, et, rest, tol):
    return brach_2d_scalar(vn, vt, wnn, wnt, wtt, e, mu, et)


@njit(cache=True, inline="always", error_model="numpy")
def _core_smith_2d(vn, vt, wnn, wnt, wtt, e, mu, et, rest, tol):
    return smith_2d_scalar(vn, vt, wnn, wnt, wtt, e, mu)


@njit(cache=True, inline="always", error_model="numpy")
def _core_routh_2d(vn, vt, wnn, wnt, wtt, e, mu, et, rest, tol):
    return routh_2d_scalar(vn, vt, wnn, wnt, wtt, e, mu, rest)


@njit(cache=True, inline="always", error_model="numpy")
def _core_cr_2d(vn, vt, wnn, wnt, wtt, e, mu, et, rest, tol):
    return chatterjee_ruina_2d_scalar(vn, vt, wnn, wnt, wtt, e, mu, et)


@njit(cache=True, inline="always", error_model="numpy")
def _core_kl_3d(vn, v1, v2, wnn, w1, w2, t11, t12, t22, e, mu, et, rest, tol):
    return kane_levinson_3d_scalar(vn, v1, v2, wnn, w1, w2, t11, t12, t22, e, mu)


@njit(cache=True, inline="always", error_model="numpy")
def _core_brach_3d(vn, v1, v2, wnn, w1, w2, t11, t12, t22, e, mu, et, rest, tol):
    return brach_3d_scalar(vn, v1, v2, wnn, w1, w2, t11, t12, t22, e, mu, et)


@njit(cache=True, inline="always", error_model="numpy")
def _core_smith_3d(vn, v1, v2, wnn, w1, w2, t11, t12, t22, e, mu, et, rest, tol):
    return smith_3d_scalar(vn, v1, v2, wnn, w1, w2, t11, t12, t22, e, mu)


@njit(cache=True, inline="always", error_model="numpy")
def _core_routh_3d(vn, v1, v2, wnn, w1, w2, t11, t12, t22, e, mu, et, rest, tol):
    return routh_3d_scalar(vn, v1, v2, wnn, w1, w2, t11, t12, t22, e, mu, rest, tol)


@njit(cache=True, inline="always", error_model="numpy")
def _core_cr_3d(vn, v1, v2, wnn, w1, w2, t11, t12, t22, e, mu, et, rest, tol):
    return chatterjee_ruina_3d_scalar(vn, v1, v2, wnn, w1, w2, t11, t12, t22, e, mu, et)


#: law id -> core with the uniform signature (for loops written once over the law)
CORES_2D = {LAW_KANE_LEVINSON: _core_kl_2d, LAW_BRACH: _core_brach_2d,
            LAW_SMITH: _core_smith_2d, LAW_ROUTH: _core_routh_2d,
            LAW_CHATTERJEE_RUINA: _core_cr_2d}
CORES_3D = {LAW_KANE_LEVINSON: _core_kl_3d, LAW_BRACH: _core_brach_3d,
            LAW_SMITH: _core_smith_3d, LAW_ROUTH: _core_routh_3d,
            LAW_CHATTERJEE_RUINA: _core_cr_3d}


# ---- checks ---------------------------------------------------------------------------------
@njit(cache=True, inline="always", error_model="numpy")
def _row_ok(params, r, lo, hi):
    """Parameter row ``r`` within [lo, hi] slot by slot, every value finite."""
    for k in range(N_PARAMS):
        x = params[r, k]
        if not (x >= lo[k] and x <= hi[k] and x - x == 0.0):
            return False
    return True


@njit(cache=True, inline="always", error_model="numpy")
def _asym_bad(x, y, dmax, omax, rtol):
    """2D: |x - y| beyond ``rtol`` of max|W| = max(dmax, omax) (diagonal, off-diagonal
    maxima; entries finite here)."""
    return abs(x - y) > rtol * max(dmax, omax)


@njit(cache=True, inline="always", error_model="numpy")
def _spd3(a, b, c, d, e, f):
    """W = [[a, b, c], [b, d, e], [c, e, f]] positive definite by Sylvester's criterion,
    division-free: ``a > 0``, ``a d - b^2 > 0`` (Kahan's FMA ``det2k``: exact sign) and
    ``det W > 0`` by the first row with FMA cofactors. These are the products of the pivots
    of ``W = L D L^T`` (``D_1 = a``, ``D_1 D_2 = a d - b^2``, ``D_1 D_2 D_3 = det W``)."""
    if not (a > 0.0 and det2k(a, d, b, b) > 0.0):
        return False
    det = a * det2k(d, f, e, e) - b * det2k(b, f, c, e) + c * det2k(b, e, c, d)
    return det > 0.0


# ---- generic loops (inlined into each entry) ------------------------------------------------
@njit(cache=True, inline="always", error_model="numpy")
def _loop_2d(core, v, W, params, lo, hi, check, sym_rtol, gain_rtol, P_out, vf_out, dE_out,
             gain_out, mode_out):
    n = v.shape[0]
    last = params.shape[0] - 1
    nbad = 0
    first_bad = n
    nfail = 0
    first_fail = n
    rows = last > 0                         # one parameter row per contact: check each
    shared_bad = check and not rows and not _row_ok(params, 0, lo, hi)
    for i in prange(n):
        r = min(np.int64(i), last)          # prange indices are unsigned
        vn = v[i, 0]
        vt = v[i, 1]
        wnn = W[i, 0, 0]
        wnt = W[i, 0, 1]
        wtt = W[i, 1, 1]
        bad = 0
        if check:
            wtn = W[i, 1, 0]
            if not ((vn - vn) + (vt - vt) + (wnn - wnn) + (wnt - wnt) + (wtn - wtn)
                    + (wtt - wtt) == 0.0):          # x - x is NaN for inf and NaN
                bad = BAD_V if not ((vn - vn) + (vt - vt) == 0.0) else BAD_W
            elif _asym_bad(wnt, wtn, max(abs(wnn), abs(wtt)), max(abs(wnt), abs(wtn)),
                           sym_rtol):
                bad = BAD_SYM
            else:
                wnt = 0.5 * (wnt + wtn)
                if not (wnn > 0.0 and det2k(wnn, wtt, wnt, wnt) > 0.0):
                    bad = BAD_SPD
                elif rows and not _row_ok(params, r, lo, hi):
                    bad = BAD_PARAM
            if shared_bad and bad == 0:
                bad = BAD_PARAM
        if bad != 0:
            mode = bad
            p0 = 0.0
            p1 = 0.0
            nbad += 1
            first_bad = min(first_bad, np.int64(i))
        else:
            mode, p0, p1 = core(vn, vt, wnn, wnt, wtt, params[r, P_E], params[r, P_MU],
                                params[r, P_ET], params[r, P_REST], params[r, P_TOL])
            if mode < 0:
                nfail += 1
                first_fail = min(first_fail, np.int64(i))
        f0 = vn + wnn * p0 + wnt * p1
        f1 = vt + wnt * p0 + wtt * p1
        mode_out[i] = mode
        P_out[i, 0] = p0
        P_out[i, 1] = p1
        vf_out[i, 0] = f0
        vf_out[i, 1] = f1
        dE = 0.5 * (p0 * (vn + f0) + p1 * (vt + f1))
        dE_out[i] = dE
        gain_out[i] = dE > gain_rtol * (0.5 * (abs(p0) * (abs(vn) + abs(f0))
                                               + abs(p1) * (abs(vt) + abs(f1))))
    return nbad, first_bad, nfail, first_fail


@njit(cache=True, inline="always", error_model="numpy")
def _loop_3d(core, v, W, params, lo, hi, check, sym_rtol, gain_rtol, P_out, vf_out, dE_out,
             gain_out, mode_out):
    n = v.shape[0]
    last = params.shape[0] - 1
    nbad = 0
    first_bad = n
    nfail = 0
    first_fail = n
    rows = last > 0                         # one parameter row per contact: check each
    shared_bad = check and not rows and not _row_ok(params, 0, lo, hi)
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
        bad = 0
        if check:
            l1 = W[i, 1, 0]
            l2 = W[i, 2, 0]
            l12 = W[i, 2, 1]
            if not ((vn - vn) + (v1 - v1) + (v2 - v2) + (wnn - wnn) + (w1 - w1) + (w2 - w2)
                    + (t11 - t11) + (t12 - t12) + (t22 - t22) + (l1 - l1) + (l2 - l2)
                    + (l12 - l12) == 0.0):           # x - x is NaN for inf and NaN
                bad = BAD_V if not ((vn - vn) + (v1 - v1) + (v2 - v2) == 0.0) else BAD_W
            else:
                asym = max(max(abs(w1 - l1), abs(w2 - l2)), abs(t12 - l12))
                if asym > sym_rtol * max(max(abs(wnn), abs(t11)), abs(t22)):
                    # rare: the full scale max|W| (the diagonal bounds it for SPD W)
                    scale = max(max(max(abs(wnn), abs(t11)), max(abs(t22), abs(w1))),
                                max(max(abs(w2), abs(t12)),
                                    max(abs(l1), max(abs(l2), abs(l12)))))
                    if asym > sym_rtol * scale:
                        bad = BAD_SYM
                if bad == 0:
                    w1 = 0.5 * (w1 + l1)
                    w2 = 0.5 * (w2 + l2)
                    t12 = 0.5 * (t12 + l12)
                    if not _spd3(wnn, w1, w2, t11, t12, t22):
                        bad = BAD_SPD
                    elif rows and not _row_ok(params, r, lo, hi):
                        bad = BAD_PARAM
            if shared_bad and bad == 0:
                bad = BAD_PARAM
        if bad != 0:
            mode = bad
            p0 = 0.0
            p1 = 0.0
            p2 = 0.0
            nbad += 1
            first_bad = min(first_bad, np.int64(i))
        else:
            mode, p0, p1, p2 = core(vn, v1, v2, wnn, w1, w2, t11, t12, t22, params[r, P_E],
                                    params[r, P_MU], params[r, P_ET], params[r, P_REST],
                                    params[r, P_TOL])
            if mode < 0:
                nfail += 1
                first_fail = min(first_fail, np.int64(i))
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
        dE = 0.5 * (p0 * (vn + f0) + p1 * (v1 + f1) + p2 * (v2 + f2))
        dE_out[i] = dE
        gain_out[i] = dE > gain_rtol * (0.5 * (abs(p0) * (abs(vn) + abs(f0))
                                               + abs(p1) * (abs(v1) + abs(f1))
                                               + abs(p2) * (abs(v2) + abs(f2))))
    return nbad, first_bad, nfail, first_fail


# ---- one entry per (law, dimension): compiles that law only, cached on disk ----------------
_OPTS = dict(cache=True, parallel=True, error_model="numpy")


@njit(**_OPTS)
def batch_2d_kane_levinson(v, W, params, lo, hi, check, sym_rtol, gain_rtol, P_out, vf_out,
                           dE_out, gain_out, mode_out):
    return _loop_2d(_core_kl_2d, v, W, params, lo, hi, check, sym_rtol, gain_rtol, P_out,
                    vf_out, dE_out, gain_out, mode_out)


@njit(**_OPTS)
def batch_2d_brach(v, W, params, lo, hi, check, sym_rtol, gain_rtol, P_out, vf_out, dE_out,
                   gain_out, mode_out):
    return _loop_2d(_core_brach_2d, v, W, params, lo, hi, check, sym_rtol, gain_rtol, P_out,
                    vf_out, dE_out, gain_out, mode_out)


@njit(**_OPTS)
def batch_2d_smith(v, W, params, lo, hi, check, sym_rtol, gain_rtol, P_out, vf_out, dE_out,
                   gain_out, mode_out):
    return _loop_2d(_core_smith_2d, v, W, params, lo, hi, check, sym_rtol, gain_rtol, P_out,
                    vf_out, dE_out, gain_out, mode_out)


@njit(**_OPTS)
def batch_2d_routh(v, W, params, lo, hi, check, sym_rtol, gain_rtol, P_out, vf_out, dE_out,
                   gain_out, mode_out):
    return _loop_2d(_core_routh_2d, v, W, params, lo, hi, check, sym_rtol, gain_rtol, P_out,
                    vf_out, dE_out, gain_out, mode_out)


@njit(**_OPTS)
def batch_2d_chatterjee_ruina(v, W, params, lo, hi, check, sym_rtol, gain_rtol, P_out,
                              vf_out, dE_out, gain_out, mode_out):
    return _loop_2d(_core_cr_2d, v, W, params, lo, hi, check, sym_rtol, gain_rtol, P_out,
                    vf_out, dE_out, gain_out, mode_out)


@njit(**_OPTS)
def batch_3d_kane_levinson(v, W, params, lo, hi, check, sym_rtol, gain_rtol, P_out, vf_out,
                           dE_out, gain_out, mode_out):
    return _loop_3d(_core_kl_3d, v, W, params, lo, hi, check, sym_rtol, gain_rtol, P_out,
                    vf_out, dE_out, gain_out, mode_out)


@njit(**_OPTS)
def batch_3d_brach(v, W, params, lo, hi, check, sym_rtol, gain_rtol, P_out, vf_out, dE_out,
                   gain_out, mode_out):
    return _loop_3d(_core_brach_3d, v, W, params, lo, hi, check, sym_rtol, gain_rtol, P_out,
                    vf_out, dE_out, gain_out, mode_out)


@njit(**_OPTS)
def batch_3d_smith(v, W, params, lo, hi, check, sym_rtol, gain_rtol, P_out, vf_out, dE_out,
                   gain_out, mode_out):
    return _loop_3d(_core_smith_3d, v, W, params, lo, hi, check, sym_rtol, gain_rtol, P_out,
                    vf_out, dE_out, gain_out, mode_out)


@njit(**_OPTS)
def batch_3d_routh(v, W, params, lo, hi, check, sym_rtol, gain_rtol, P_out, vf_out, dE_out,
                   gain_out, mode_out):
    return _loop_3d(_core_routh_3d, v, W, params, lo, hi, check, sym_rtol, gain_rtol, P_out,
                    vf_out, dE_out, gain_out, mode_out)


@njit(**_OPTS)
def batch_3d_chatterjee_ruina(v, W, params, lo, hi, check, sym_rtol, gain_rtol, P_out,
                              vf_out, dE_out, gain_out, mode_out):
    return _loop_3d(_core_cr_3d, v, W, params, lo, hi, check, sym_rtol, gain_rtol, P_out,
                    vf_out, dE_out, gain_out, mode_out)


_ENTRIES = {
    2: {LAW_KANE_LEVINSON: batch_2d_kane_levinson, LAW_BRACH: batch_2d_brach,
        LAW_SMITH: batch_2d_smith, LAW_ROUTH: batch_2d_routh,
        LAW_CHATTERJEE_RUINA: batch_2d_chatterjee_ruina},
    3: {LAW_KANE_LEVINSON: batch_3d_kane_levinson, LAW_BRACH: batch_3d_brach,
        LAW_SMITH: batch_3d_smith, LAW_ROUTH: batch_3d_routh,
        LAW_CHATTERJEE_RUINA: batch_3d_chatterjee_ruina},
}


def kernel_for(law_id, d):
    """The batch entry of law ``law_id`` (a ``common.LAW_*`` id) in dimension ``d`` (2, 3)."""
    try:
        return _ENTRIES[d][law_id]
    except KeyError:
        raise ValueError(f"no batch kernel for law id {law_id!r} in dimension {d!r}") from None


NO_RANGE_LO = np.full(N_PARAMS, -np.inf)
NO_RANGE_HI = np.full(N_PARAMS, np.inf)
