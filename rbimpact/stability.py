"""Stability suite on stiff and extreme cases (issue 6): every law, 2D and 3D, and the
event-driven steppers, with a table, a CSV and a pass/fail verdict.

    >>> text, rows, ok = stability_report(quick=True)

``stability_report`` runs two matrices and returns ``(text, rows, ok)``: the printed table,
one ``Row`` per cell and ``ok = False`` when a cell FAILs (``rbimpact stability`` then
exits non-zero).

**Laws matrix.** Every law variant (``LAW_VARIANTS``: the five laws, Routh with each
restitution kind) in 2D and 3D on the cases of ``law_cases`` (e = 0, 1, -1 for Brach;
mu = 0, 1e-12, 1e6; W from two bodies with mass ratios 1e-9 and 1e9; a thin rod with
inertia ratio 1e-8; grazing v_N = -1e-14; v_T = 1e-300, subnormal and exactly 0; speeds
1e8; cond(W) = 1e12; nearly singular and Painleve-type coupling; random W, v, e, mu over
many decades). A cell is a few sub-evaluations (a small (e, mu) grid); per cell:

* outputs finite, or ``NoSolutionError`` where the law's kernel documents it (``DOC-ERR``,
  ``DOCUMENTED_ERRORS``); an error a kernel documents as impossible for SPD ``W`` FAILs;
* ``dE_rel = dE / K0`` (``K0 = v.W^-1 v / 2``, the contact-space kinetic energy); for the
  laws that never create energy (smith, chatterjee_ruina, routh energetic/poisson) a gain
  ``dE > ENERGY_RTOL * E_scale`` FAILs, ``E_scale = max(K0, sum_k |P_k|(|v_k|+|v_fk|)/2)``
  (the round-off scale of ``dE``); Routh 3D adds ``ENERGY_TOL_FACTOR * tol``;
* the law's own residual (``law_residual``), dimensionless: how well ``v_f`` satisfies the
  law's defining equations, relative to ``s = |v| + ||W||_2 |P|`` (m/s, the size of the
  terms of ``v_f = v + W P``); FAIL above ``RESID_RTOL`` (Routh 3D:
  ``RESID_TOL_FACTOR_ROUTH3D * tol``, its integration is to ``tol``);
* iterations (``count_iterations``; 0 for closed forms) and time per kernel call.

**Stepper matrix** (``stepper_cases``): Zeno with e = 0.99, 1e4 m/s impacts, a box landing
flat under both policies (2D and 3D), a rod spinning at 1e4 rad/s grazing the floor,
1e6 elastic impacts, Galperin's billiard with mass ratio 1e6 (3141 collisions). Per scene:
the run ends as expected, energy is never created when every law involved never creates
it (``STEP_ENERGY_RTOL``), and no body is ever below a plane by more than
``PEN_ATOL + PEN_RTOL * L`` at densely sampled times (``L`` the scene's length scale).
"""
import csv
import math
import sys
import time
import types
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np

from .errors import NoSolutionError, SimulationError

__all__ = ["stability_report", "Row", "LAW_VARIANTS", "law_cases", "check_impact",
           "law_residual", "count_iterations", "run_law_matrix", "run_stepper_matrix",
           "format_table", "write_csv", "RESID_RTOL", "ENERGY_RTOL"]

# ---- named tolerances --------------------------------------------------------------------
RESID_RTOL = 1e-10
"""Law residual tolerance (dimensionless, relative to s = |v| + ||W||_2 |P|) for the laws
solved in closed form or by root finding to round-off (K&L, Brach, Smith, C&R, Routh 2D).
Round-off alone gives ~1e-15; this leaves 1e5 ulps of margin."""
RESID_TOL_FACTOR_ROUTH3D = 100.0
"""Routh 3D integrates to a relative ``tol`` (default 1e-10, kernel docstring): its residual
(v_f at ``tol`` against v_f at ``ROUTH3D_REF_TOL``) must stay below this factor times tol."""
ROUTH3D_REF_TOL = 1e-13
"""Reference tolerance of the Routh 3D self-convergence residual."""
ENERGY_RTOL = 1e-12
"""Energy gain tolerance of the never-gain laws, relative to E_scale (the same value as
``rbimpact.laws.ENERGY_GAIN_RTOL``)."""
ENERGY_TOL_FACTOR = 100.0
"""Routh 3D: the energy tolerance adds this factor times the integration ``tol``."""
N_TIMING = 200
"""Kernel calls averaged for the time column (per sub-evaluation, after a warm-up)."""
EPS = np.finfo(float).eps

# ---- law variants ---------------------------------------------------------------------------
#: (label, law name, fixed parameters)
LAW_VARIANTS = (
    ("kane_levinson", "kane_levinson", {}),
    ("brach", "brach", {}),
    ("smith", "smith", {}),
    ("routh-energetic", "routh", {"restitution": "energetic"}),
    ("routh-poisson", "routh", {"restitution": "poisson"}),
    ("routh-newton", "routh", {"restitution": "newton"}),
    ("chatterjee_ruina", "chatterjee_ruina", {}),
)
NEVER_GAIN = ("smith", "chatterjee_ruina", "routh-energetic", "routh-poisson")
NEWTON_TYPE = ("kane_levinson", "brach", "smith", "chatterjee_ruina", "routh-newton")

#: (law, dim) -> mode codes of NoSolutionError that the kernel's docstring allows for an SPD W.
#: K&L, Brach, C&R, Smith 2D and Routh 2D document a solution for every SPD W: an error FAILs.
DOCUMENTED_ERRORS = {
    ("kane_levinson", 3): (-1, -2),   # "none was found missing ... on 1e5 random cases"
    ("smith", 3): (-1, -2),           # scan exhausted / iteration limit
    ("routh", 3): (-1, -2),           # v_N back to 0 in restitution; MAX_STEPS
}


# ============================================================================================
# contact-space W from two bodies (DESIGN §3)
# ============================================================================================
def _cross2(r, e):
    return r[0] * e[1] - r[1] * e[0]


def delassus_2d(bodies, n=(0.0, 1.0)):
    """W (2x2, normal first) of a contact with unit normal ``n`` between bodies given as
    ``(m, I, r)``: mass (kg), inertia (kg m^2), arm ``r`` from the centre of mass to the
    contact point (m). ``t = (n_y, -n_x)``."""
    n = np.asarray(n, float)
    basis = (n, np.array([n[1], -n[0]]))
    W = np.zeros((2, 2))
    for m, I, r in bodies:
        rc = [_cross2(r, e) for e in basis]
        for i in range(2):
            for j in range(2):
                W[i, j] += (basis[i] @ basis[j]) / m + rc[i] * rc[j] / I
    return W


def delassus_3d(bodies, basis=None):
    """W (3x3) for bodies ``(m, I_world (3x3), r)``, contact basis rows ``(n, t1, t2)``
    (default the floor: z, x, y)."""
    basis = np.array([[0, 0, 1.0], [1.0, 0, 0], [0, 1.0, 0]]) if basis is None else basis
    W = np.zeros((3, 3))
    for m, I, r in bodies:
        Iinv = np.linalg.inv(I)
        rc = np.array([np.cross(r, e) for e in basis])
        W += basis @ basis.T / m + rc @ Iinv @ rc.T
    return W


def _rot3(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


def _rod3(m, L, inertia_ratio=1.0, radius=0.0):
    """A rod of mass m, length L, tilted, touching the floor at its lower end (on its
    surface at ``radius`` off the axis); axial inertia = inertia_ratio * transverse."""
    R = _rot3((0.3, 1.0, 0.2), 0.9)
    It = m * L * L / 12.0
    I = R @ np.diag([It, It, inertia_ratio * It]) @ R.T
    axis = R @ np.array([0, 0, 1.0])
    side = R @ np.array([1.0, 0, 0])
    r = -0.5 * L * axis + radius * side
    if r[2] > 0:
        r = 0.5 * L * axis + radius * side
    return (m, I, r)


def _sphere3(m, R):
    return (m, 0.4 * m * R * R * np.eye(3), np.array([0.0, 0.0, R]))


def _rod2(m, L, angle=math.pi / 4, inertia=None):
    r = (-0.5 * L * math.cos(angle), -0.5 * L * math.sin(angle))
    return (m, m * L * L / 12.0 if inertia is None else inertia, r)


def _disk2(m, R):
    return (m, 0.5 * m * R * R, (0.0, R))


def _spd(eigs, seed):
    Q, _ = np.linalg.qr(np.random.default_rng(seed).normal(size=(len(eigs), len(eigs))))
    W = Q @ np.diag(eigs) @ Q.T
    return 0.5 * (W + W.T)


# ============================================================================================
# the cases
# ============================================================================================
W2_ROD = np.array([[2.5, -1.5], [-1.5, 2.5]])              # DESIGN §5 rod at 45 degrees
V2_ROD = np.array([-1.0, 1.0])
W3_SWERVE = np.array([[5.0, 1.0, -1.0], [1.0, 8.0, -2.0], [-1.0, -2.0, 3.0]])
V3_SWERVE = np.array([-4.0, -2.0, 1.0])
W3_PAINLEVE = np.array([[0.178, -0.179, -0.096], [-0.179, 0.217, 0.084],
                        [-0.096, 0.084, 0.062]])
V3_PAINLEVE = np.array([-0.5, 1.0, -0.4])
GRID = ((0.0, 0.3), (1.0, 0.3), (0.0, 5.0), (1.0, 5.0))
"""(e, mu) sub-grid of the geometric cases."""


@dataclass
class Case:
    """A named cell input: ``subs`` is a list of (v, W, params) sub-evaluations."""

    name: str
    dim: int
    subs: list
    quick: bool = False
    only: tuple = None          # law labels this case applies to (None: all)
    note: str = ""


def _grid(v, W, grid=GRID, **extra):
    return [(np.asarray(v, float), np.asarray(W, float), dict(e=e, mu=mu, **extra))
            for e, mu in grid]


def _random_subs(dim, n, seed):
    """n random contacts: W = Q diag(lambda) Q^T with lambda over 12 decades times a scale
    over 18 decades; v_N over 18 decades; v_T components over 600 decades (or 0); mu over
    18 decades (or 0); e uniform in [0, 1] (or exactly 0 or 1)."""
    rng = np.random.default_rng(seed)
    subs = []
    for _ in range(n):
        lam = 10.0 ** rng.uniform(-12, 0, size=dim)
        lam[rng.integers(dim)] = 1.0
        W = _spd(lam * 10.0 ** rng.uniform(-9, 9), int(rng.integers(1 << 31)))
        v = np.empty(dim)
        v[0] = -10.0 ** rng.uniform(-10, 8)
        for k in range(1, dim):
            x = rng.uniform()
            v[k] = 0.0 if x < 0.1 else rng.choice([-1, 1]) * 10.0 ** rng.uniform(-300, 8)
        mu = 0.0 if rng.uniform() < 0.1 else 10.0 ** rng.uniform(-12, 6)
        e = float(rng.choice([0.0, 1.0, rng.uniform()]))
        e_t = float(rng.choice([0.0, 1.0, -1.0, rng.uniform(-1, 1)]))
        subs.append((v, W, dict(e=e, mu=mu, e_t=e_t)))
    return subs


def law_cases(quick=False, n_random=None):
    """The cases of the laws matrix (``Case`` list); ``quick`` keeps the marked subset."""
    cases = []
    for dim in (2, 3):
        W0, v0 = (W2_ROD, V2_ROD) if dim == 2 else (W3_SWERVE, V3_SWERVE)
        vt = v0[1:] / np.abs(v0[1:]).max()

        def vv(vn, t):
            return np.concatenate([[vn], t * vt])
        cases += [
            Case("e=0", dim, _grid(v0, W0, ((0.0, 0.3), (0.0, 0.8))), quick=True),
            Case("e=1", dim, _grid(v0, W0, ((1.0, 0.3), (1.0, 0.8)))),
            Case("e=-1", dim, _grid(v0, W0, ((-1.0, 0.3), (-1.0, 0.8))), only=("brach",)),
            Case("mu=0", dim, _grid(v0, W0, ((0.5, 0.0), (1.0, 0.0)))),
            Case("mu=1e-12", dim, _grid(v0, W0, ((0.5, 1e-12), (1.0, 1e-12)))),
            Case("mu=1e6", dim, _grid(v0, W0, ((0.5, 1e6), (1.0, 1e6))), quick=True),
        ]
        if dim == 2:
            Wl = delassus_2d([_rod2(1e-9, 1.0), _disk2(1.0, 1.0)])
            Wh = delassus_2d([_rod2(1e9, 1.0), _disk2(1.0, 1.0)])
            Wrod = delassus_2d([_rod2(1.0, 1.0, inertia=1e-8 * 0.25)])   # I = 1e-8 m r^2
            Wc = _spd([1.0, 1e-12], 7)
            Wns = np.array([[1.0, 1.0 - 1e-9], [1.0 - 1e-9, 1.0]])
            Wp = W3_PAINLEVE[:2, :2].copy()
            vp = V3_PAINLEVE[:2].copy()
        else:
            Wl = delassus_3d([_rod3(1e-9, 1.0), _sphere3(1.0, 1.0)])
            Wh = delassus_3d([_rod3(1e9, 1.0), _sphere3(1.0, 1.0)])
            Wrod = delassus_3d([_rod3(1.0, 1.0, inertia_ratio=1e-8, radius=0.01)])
            Wc = _spd([1.0, 1e-6, 1e-12], 7)
            Wns = np.array([[1.0, 1.0 - 1e-9, 0.3], [1.0 - 1e-9, 1.0, 0.3], [0.3, 0.3, 1.0]])
            Wp, vp = W3_PAINLEVE, V3_PAINLEVE
        sub = np.finfo(float).tiny * 1e-5       # a subnormal speed (2.2e-313 m/s)
        cases += [
            Case("mass_ratio=1e-9", dim, _grid(v0, Wl)),
            Case("mass_ratio=1e9", dim, _grid(v0, Wh)),
            Case("thin_rod_I=1e-8", dim, _grid(v0, Wrod), quick=True),
            Case("grazing_vN=-1e-14", dim, _grid(vv(-1e-14, 1.0), W0), quick=True),
            Case("vT=1e-300", dim, _grid(vv(-1.0, 1e-300), W0)),
            Case("vT=subnormal", dim, _grid(vv(-1.0, sub), W0), quick=True),
            Case("vT=0", dim, _grid(vv(-1.0, 0.0), W0), quick=True),
            Case("speed=1e8", dim, _grid(1e8 * v0, W0)),
            Case("cond(W)=1e12", dim, _grid(vv(-1.0, 0.5), Wc), quick=True),
            Case("near_singular", dim, _grid(vv(-1.0, 0.2), Wns)),
            Case("painleve", dim, _grid(vp, Wp, ((0.5, 7.5), (1.0, 7.5), (0.0, 7.5))),
                 quick=True),
        ]
        nr = n_random if n_random is not None else (12 if quick else 300)
        cases.append(Case("random", dim, _random_subs(dim, nr, 1000 + dim), quick=True))
    if quick:
        cases = [c for c in cases if c.quick]
    return cases


# ============================================================================================
# one impact: run, energy, residual
# ============================================================================================
@dataclass
class Eval:
    """Outcome of one sub-evaluation."""

    status: str                 # "OK", "FAIL", "DOC-ERR"
    dE_rel: float = float("nan")
    residual: float = float("nan")
    tol: float = RESID_RTOL
    iterations: object = None  # int, or None when not measurable
    time: float = float("nan")  # s per kernel call
    note: str = ""
    mode: int = 0


def _law(label):
    for lab, name, fixed in LAW_VARIANTS:
        if lab == label:
            return name, fixed
    raise ValueError(f"unknown law variant {label!r}")


def make_law(label, params):
    """``rbimpact.Law`` of variant ``label`` with the parameters it takes from ``params``."""
    from .laws import LAWS, Law
    name, fixed = _law(label)
    takes = LAWS[name].params
    kw = {k: v for k, v in {**params, **fixed}.items() if k in takes}
    return Law(name, **kw)


def kinetic_energy(v, W):
    """K0 = v.W^-1 v / 2 (J), through a Cholesky factor (relative error ~eps sqrt(cond))."""
    from scipy.linalg import cho_factor, solve_triangular
    L = np.linalg.cholesky(W)
    y = solve_triangular(L, v, lower=True)
    return 0.5 * float(y @ y)


def _unit(x):
    n = np.linalg.norm(x)
    return x / n if n > 0 else x * 0.0


def _dir_defect(x, d):
    """|x - max(x.d, 0) d| for a unit d: the part of x not along +d."""
    return float(np.linalg.norm(x - max(float(x @ d), 0.0) * d))


def law_residual(label, v, W, params, P, mode, tol=None):
    """The law's own residual (dimensionless; see the module docstring) and its tolerance.

    Every law: ``P_N >= 0`` and the cone ``|P_T| <= mu P_N`` (as velocities ``||W|| x``).
    Newton-type laws: ``|v_fN + e v_N|``. K&L: stick ``v_fT = 0``; slip ``|P_T| = mu P_N``
    and ``v_fT = lambda u``, ``lambda >= 0``, ``u = -P_T/|P_T|``. Brach: stick ``v_fT = -e_t
    v_T``; slip on the cone with ``P_T`` along ``P*_T`` (``P* = W^-1 (v_f* - v)``, measured
    as the velocity perturbation ``|P*_T,perp| / ||W^-1||`` relative to ``|v| + ||W|| |P*|``).
    C&R: ``v_fT - v_T - (1+e) W_TN P_IN = -k v_T^I`` with ``k = 1 + e_t`` (stick) or
    ``0 <= k``, ``|P_T| = mu P_N`` (slip). Smith: ``|P_T/(mu P_N) + g(a, b)| max(|a|,|b|)``.
    Routh 2D: exact rational path (``routh2d_residual``). Routh 3D: ``|v_f(tol) -
    v_f(ROUTH3D_REF_TOL)|`` (self-convergence). Returns ``(residual, tolerance)``."""
    name, fixed = _law(label)
    d = len(v)
    e = params.get("e", 0.0)
    mu = params.get("mu", 0.0)
    et = params.get("e_t", 0.0)
    Wn = np.linalg.norm(W, 2)
    vf = v + W @ P
    s = np.linalg.norm(v) + Wn * np.linalg.norm(P)
    if s == 0.0 or mode == 0:
        return 0.0, RESID_RTOL
    PT = P[1:]
    nPT = np.linalg.norm(PT)
    r = [max(0.0, -P[0]) * Wn / s, max(0.0, nPT - mu * P[0]) * Wn / s]
    rtol = RESID_RTOL
    if label in NEWTON_TYPE:
        r.append(abs(vf[0] + e * v[0]) / s)
    if name == "kane_levinson":
        if mode == 1:
            r.append(np.linalg.norm(vf[1:]) / s)
        elif mu > 0:
            r.append(abs(nPT - mu * P[0]) * Wn / s)
            r.append(_dir_defect(vf[1:], -_unit(PT)) / s)
    elif name == "brach":
        if mode == 1:
            r.append(np.linalg.norm(vf[1:] + et * v[1:]) / s)
        elif mu > 0:
            r.append(abs(nPT - mu * P[0]) * Wn / s)
            target = np.concatenate([[-e * v[0]], -et * v[1:]])
            Ps = np.linalg.solve(W, target - v)
            if nPT > 0:
                winv = 1.0 / np.linalg.eigvalsh(W)[0]
                ss = np.linalg.norm(v) + Wn * np.linalg.norm(Ps)
                r.append(_dir_defect(Ps[1:], _unit(PT)) / winv / ss)
    elif name == "chatterjee_ruina":
        pin = -v[0] / W[0, 0]
        vTI = v[1:] + W[1:, 0] * pin
        delta = vf[1:] - v[1:] - (1 + e) * W[1:, 0] * pin
        n2 = float(vTI @ vTI)
        k = -float(delta @ vTI) / n2 if n2 > 0 else 0.0
        k = min(max(k, 0.0), 1.0 + et)
        r.append(np.linalg.norm(delta + k * vTI) / s)
        if mode == 1:
            r.append(abs(k - (1 + et)) * math.sqrt(n2) / s)
        elif mu > 0:
            r.append(abs(nPT - mu * P[0]) * Wn / s)
    elif name == "smith":
        a = v[1:]
        b = vf[1:]
        na, nb = np.linalg.norm(a), np.linalg.norm(b)
        if mu == 0:
            r.append(nPT * Wn / s)
        elif mode == 1:                      # set-valued a = b = 0: stick
            r.append(nb / s)
        else:
            den = na * na + nb * nb
            g = (na * a + nb * b) / den if den > 0 else 0.0 * a
            r.append(np.linalg.norm(PT / (mu * P[0]) + g) * max(na, nb) / s)
    elif name == "routh":
        if d == 2:
            r.append(routh2d_residual(v, W, params, fixed["restitution"], P))
        else:
            t = 1e-10 if tol is None else tol
            rtol = RESID_TOL_FACTOR_ROUTH3D * t
            ref = make_law(label, {**params, "tol": ROUTH3D_REF_TOL})
            try:
                Pr = ref.resolve(v, W).P
                r.append(np.linalg.norm(W @ (P - Pr)) / s)
            except NoSolutionError as exc:
                r.append(math.inf)
    res = max(r)
    return (res if np.isfinite(res) else math.inf), rtol


# ---- Routh 2D: exact rational path ----------------------------------------------------------
def routh2d_path(v, W, mu):
    """Routh's planar path in exact rational arithmetic: list of segments
    ``(p0, p1, v_N(p0), kN, P_T(p0), gT)`` (p1 may be None: unbounded) with ``v_N`` linear
    of slope ``kN`` and ``dP_T/dp = gT`` on each."""
    F = Fraction
    vN, vT = F(v[0]), F(v[1])
    a, b, c = F(W[0, 0]), F(W[0, 1]), F(W[1, 1])
    mu = F(mu)
    stick_ok = abs(b) <= mu * c
    if vT == 0:
        s = 0 if stick_ok else (1 if b > 0 else -1)
    else:
        s = 1 if vT > 0 else -1
    segs = []
    p, PT = F(0), F(0)
    for _ in range(3):
        if s == 0:
            kN, gT, h = a - b * b / c, -b / c, None
        else:
            kN, gT = a - mu * s * b, -mu * s
            kT = b - mu * s * c
            h = -vT / kT if s * kT < 0 else None
        segs.append((p, None if h is None else p + h, vN, kN, PT, gT))
        if h is None:
            break
        p += h
        vN += kN * h
        PT += gT * h
        vT = F(0)
        s = 0 if stick_ok else -s
    return segs


def _path_at(segs, p):
    """(v_N, P_T, Wk) at impulse p: normal velocity, tangential impulse, int_0^p v_N."""
    Wk = Fraction(0)
    for p0, p1, vN0, kN, PT0, gT in segs:
        end = p if p1 is None or p <= p1 else p1
        h = end - p0
        Wk += h * (vN0 + kN * h / 2)
        if p1 is None or p <= p1:
            return vN0 + kN * h, PT0 + gT * h, Wk
    raise AssertionError("unreachable")


def _compression_end(segs):
    for p0, p1, vN0, kN, PT0, gT in segs:
        if kN > 0:
            pc = p0 - vN0 / kN
            if pc >= p0 and (p1 is None or pc <= p1):
                return pc
    return None


def routh2d_residual(v, W, params, restitution, P):
    """Residual of Routh 2D at the kernel's ``P`` (exact rational evaluation): the velocity
    defect ``|W (P - P_path(P_N))|`` and the termination condition at ``P_N`` (poisson:
    ``W_NN |P_N - (1+e) p_c|``; newton: ``|v_N(P_N) + e v_N|``; energetic: the work defect
    ``|int_0^P_N v_N dp - (1-e^2) W_c| / P_N``; e = 0: ``|v_N(P_N)|``), relative to
    ``s = |v| + ||W|| |P|``."""
    e = Fraction(params.get("e", 0.0))
    segs = routh2d_path(v, W, params.get("mu", 0.0))
    pN = Fraction(P[0])
    vN, PT, Wk = _path_at(segs, pN)
    s = np.linalg.norm(v) + np.linalg.norm(W, 2) * np.linalg.norm(P)
    dP = np.array([0.0, float(Fraction(P[1]) - PT)])
    r = [np.linalg.norm(W @ dP)]
    pc = _compression_end(segs)
    if pc is None:
        return math.inf
    _, _, Wc = _path_at(segs, pc)
    if e == 0:
        r.append(abs(float(vN)))
    elif restitution == "poisson":
        r.append(W[0, 0] * abs(float(pN - (1 + e) * pc)))
    elif restitution == "newton":
        r.append(abs(float(vN + e * Fraction(v[0]))))
    else:
        r.append(abs(float(Wk - (1 - e * e) * Wc)) / float(pN) if pN > 0 else math.inf)
    return max(r) / s


# ---- iterations: the kernel's own code run as Python, with counters --------------------------
_SHADOWS = {}


def _shadow(modname):
    """The kernel module ``modname`` with every njit function replaced by its Python
    source function (same code objects, globals in a private namespace)."""
    if modname in _SHADOWS:
        return _SHADOWS[modname]
    import importlib
    from numba.core.dispatcher import Dispatcher
    mod = importlib.import_module(modname)
    ns = dict(vars(mod))
    _SHADOWS[modname] = ns
    for key, obj in list(ns.items()):
        if isinstance(obj, Dispatcher):
            f = obj.py_func
            if f.__module__ == modname:
                ns[key] = types.FunctionType(f.__code__, ns, f.__name__, f.__defaults__,
                                             f.__closure__)
            else:
                ns[key] = _shadow(f.__module__)[f.__name__]
    return ns


#: (law, dim) -> (kernel function, counted functions, counted source lines, unit)
_COUNTERS = {
    ("kane_levinson", 3): ("kane_levinson_3d", ("_g", "_dg"), (), "g evals"),
    ("smith", 2): ("smith_2d", (), ("dq = c1 + t * (2.0 * c2",
                                    "if c0 + h * (c1 + h * (c2 + h * c3)) > 0.0"), "it"),
    ("smith", 3): ("smith_3d", ("_full_3d", "_inner_3d"), (), "F evals"),
    ("routh", 3): ("routh_3d", (), ("nstep += 1",), "RK steps"),
}
CLOSED_FORM = {("kane_levinson", 2), ("brach", 2), ("brach", 3), ("chatterjee_ruina", 2),
               ("chatterjee_ruina", 3), ("routh", 2)}


def count_iterations(law, v, W, P_ref=None):
    """Iterations of ``law`` (a ``Law``) on one contact: 0 for closed forms; else the
    count of the kernel's own loop run as Python code (``_COUNTERS``: Smith 2D Halley
    iterations plus bracket doublings, Smith 3D residual evaluations, K&L 3D evaluations of
    its trigonometric polynomial, Routh 3D Runge-Kutta step attempts); None when not
    measurable (the Python run raises, e.g. a float division by zero that the kernel does
    in IEEE arithmetic, or does not reproduce ``P_ref``)."""
    d = len(v)
    key = (law.name, d)
    if key in CLOSED_FORM or law.params[1] == 0.0 or v[0] >= 0:
        return 0
    if key not in _COUNTERS:
        return None
    fname, funcs, lines, unit = _COUNTERS[key]
    ns = _shadow(f"rbimpact.kernels.{law.name}")
    counts = [0]
    saved = {}
    for f in funcs:
        saved[f] = ns[f]

        def wrap(*a, _f=saved[f]):
            counts[0] += 1
            return _f(*a)
        ns[f] = wrap
    targets = {}
    if lines:
        import inspect
        for obj in list(ns.values()):
            if isinstance(obj, types.FunctionType) and obj.__globals__ is ns:
                try:
                    src, start = inspect.getsourcelines(obj)
                except (OSError, TypeError):
                    continue
                for i, text in enumerate(src):
                    if any(m in text for m in lines):
                        targets.setdefault(obj.__code__, set()).add(start + i)

    def tracer(frame, event, arg):
        if frame.f_code in targets:
            lines_here = targets[frame.f_code]

            def local(fr, ev, a):
                if ev == "line" and fr.f_lineno in lines_here:
                    counts[0] += 1
                return local
            return local
        return None
    P = np.zeros(d)
    old = sys.gettrace()
    try:
        if targets:
            sys.settrace(tracer)
        with np.errstate(all="ignore"):
            ns[fname](np.asarray(v, float), np.asarray(W, float), law.params.copy(), P)
    except Exception:
        return None
    finally:
        if targets:
            sys.settrace(old)
        ns.update(saved)
    if P_ref is not None:
        scale = np.abs(P_ref).max()
        if not np.all(np.abs(P - P_ref) <= 1e-9 * scale + 1e-300):
            return None
    return counts[0]


def _time_kernel(law, v, W, n=N_TIMING):
    kern = law.kernel_2d if len(v) == 2 else law.kernel_3d
    P = np.zeros(len(v))
    par = law.params
    Wc = np.ascontiguousarray(0.5 * (W + W.T))
    kern(v, Wc, par, P)
    t0 = time.perf_counter()
    for _ in range(n):
        kern(v, Wc, par, P)
    return (time.perf_counter() - t0) / n


def exact_dE(v, W, P):
    """dE = P.v + P.W.P / 2 (J) in exact rational arithmetic from the float inputs, so that
    the energy check judges the kernel's impulse and not the round-off of evaluating dE."""
    F = Fraction
    Pf = [F(x) for x in P]
    vf = [F(x) for x in v]
    d = len(Pf)
    q = sum(Pf[i] * F(W[i, j]) * Pf[j] for i in range(d) for j in range(d))
    return float(sum(Pf[i] * vf[i] for i in range(d)) + q / 2)


def kernel_det(W):
    """The determinant the 2D/3D kernels test for positive definiteness (float, same
    formula: ``W_NN W_TT - W_NT^2`` in 2D, ``_scalar3.det3s`` cofactors in 3D)."""
    if len(W) == 2:
        return W[0, 0] * W[1, 1] - W[0, 1] * W[0, 1]
    a, b, c, d, e, f = W[0, 0], W[0, 1], W[0, 2], W[1, 1], W[1, 2], W[2, 2]
    return a * (d * f - e * e) + b * (c * e - b * f) + c * (b * e - c * d)


def _cond(W):
    lam = np.linalg.eigvalsh(W)
    return float(lam[-1] / lam[0]) if lam[0] > 0 else math.inf


def check_impact(label, v, W, params, iterations=True, timing=True, n_timing=N_TIMING):
    """Run law variant ``label`` on one contact and judge it (an ``Eval``)."""
    name, fixed = _law(label)
    d = len(v)
    v = np.asarray(v, float)
    W = 0.5 * (np.asarray(W, float) + np.asarray(W, float).T)
    law = make_law(label, params)
    tol = law.params[4] if (name == "routh" and d == 3) else None
    ev = Eval("OK")
    if timing:
        ev.time = _time_kernel(law, v, W, n_timing)
    try:
        with np.errstate(all="ignore"):
            imp = law.resolve(v, W)
    except NoSolutionError as exc:
        code = exc.mode_code
        ev.mode = code
        spd = True
        try:
            np.linalg.cholesky(W)
        except np.linalg.LinAlgError:
            spd = False
        if spd and not kernel_det(W) > 0:
            ev.status = "FAIL"
            ev.note = (f"NoSolutionError mode {code}: SPD W (Cholesky succeeds, cond "
                       f"{_cond(W):.1e}) rejected, kernel determinant {kernel_det(W):.3g} "
                       f"<= 0 by cancellation")
        elif code in DOCUMENTED_ERRORS.get((name, d), ()):
            ev.status, ev.note = "DOC-ERR", f"NoSolutionError mode {code}"
        else:
            ev.status = "FAIL"
            ev.note = (f"NoSolutionError mode {code}: the kernel documents a solution for "
                       f"every SPD W")
        return ev
    except Exception as exc:                 # undocumented exception
        ev.status, ev.note = "FAIL", f"{type(exc).__name__}: {exc}"[:200]
        return ev
    ev.mode = imp.mode_code
    P, vf = imp.P, imp.v_f
    if not (np.all(np.isfinite(P)) and np.all(np.isfinite(vf)) and np.isfinite(imp.dE)):
        ev.status, ev.note = "FAIL", f"non-finite output P = {P.tolist()}"
        return ev
    K0 = kinetic_energy(v, W)
    dE = exact_dE(v, W, P)
    ev.dE_rel = dE / K0 if K0 > 0 else 0.0
    escale = max(K0, 0.5 * float(np.sum(np.abs(P) * (np.abs(v) + np.abs(vf)))))
    etol = ENERGY_RTOL + (ENERGY_TOL_FACTOR * tol if tol else 0.0)
    notes = []
    if dE > etol * escale:
        if label in NEVER_GAIN:
            ev.status = "FAIL"
            hint = (" (below eps*cond(W)*E_scale: forward error of a cancelling formula)"
                    if dE <= EPS * _cond(W) * escale else "")
            notes.append(f"energy gain dE/E_scale = {dE / escale:.2g} > {etol:.0e}{hint}")
        else:
            notes.append("gain (allowed)")
    if P[0] < 0:
        ev.status = "FAIL"
        notes.append(f"negative normal impulse P_N = {P[0]:.3g}")
    with np.errstate(all="ignore"):
        ev.residual, ev.tol = law_residual(label, v, W, params, P, imp.mode_code, tol)
    if not ev.residual <= ev.tol:
        ev.status = "FAIL"
        hint = (" (below eps*cond(W): cancellation)"
                if ev.residual <= EPS * _cond(W) else "")
        notes.append(f"residual {ev.residual:.2g} > {ev.tol:.0e}{hint}")
    ev.note = "; ".join(notes)
    if iterations:
        ev.iterations = count_iterations(law, v, W, P)
    return ev


# ============================================================================================
# rows and the table
# ============================================================================================
@dataclass
class Row:
    """One line of the report: a law cell or a stepper scene."""

    kind: str            # "law" or "stepper"
    name: str            # law variant or scene
    case: str
    dim: int
    status: str          # OK, FAIL, DOC-ERR, NOT-RUN
    dE_rel: float        # law: max dE/K0; stepper: max relative energy increase
    residual: float      # law residual / stepper worst penetration (relative to its tol)
    tol: float
    iterations: str
    time: float          # law: s per kernel call (median); stepper: wall time of the run (s)
    n: int = 1           # sub-evaluations
    note: str = ""
    repro: str = ""

    def fields(self):
        return [self.kind, self.name, self.case, self.dim, self.status, _fmt(self.dE_rel),
                _fmt(self.residual), _fmt(self.tol), self.iterations, _fmt_time(self.time),
                self.n, self.note, self.repro]


FIELDS = ["kind", "law/scene", "case", "dim", "status", "dE_rel", "residual", "tol",
          "iters", "time", "n", "note", "reproducer"]


def _fmt(x):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "-"
    if x == 0:
        return "0"
    return f"{x:.2e}"


def _fmt_time(t):
    if t is None or math.isnan(t):
        return "-"
    if t < 1e-3:
        return f"{t * 1e6:.2f}us"
    if t < 1.0:
        return f"{t * 1e3:.1f}ms"
    return f"{t:.2f}s"


def _repro(label, v, W, params):
    name, fixed = _law(label)
    kw = ", ".join(f"{k}={x!r}" for k, x in {**params, **fixed}.items()
                   if k in ("e", "mu", "e_t", "restitution"))
    return (f"rbimpact.resolve({name!r}, {np.asarray(v).tolist()!r}, "
            f"{np.asarray(W).tolist()!r}, {kw})")


def run_law_cell(label, case, iterations=True):
    """Evaluate one (law variant, case) cell; returns a ``Row``."""
    evs = []
    for v, W, params in case.subs:
        evs.append((check_impact(label, v, W, params, iterations=iterations,
                                 n_timing=N_TIMING if len(case.subs) <= 8 else 20),
                    v, W, params))
    status = "OK"
    if any(e.status == "DOC-ERR" for e, *_ in evs):
        status = "DOC-ERR"
    fails = [(e, v, W, p) for e, v, W, p in evs if e.status == "FAIL"]
    if fails:
        status = "FAIL"
    dE = [e.dE_rel for e, *_ in evs if not math.isnan(e.dE_rel)]
    res = [(e.residual / e.tol, e) for e, *_ in evs if not math.isnan(e.residual)]
    worst = max(res, key=lambda x: x[0])[1] if res else None
    its = [e.iterations for e, *_ in evs]
    key = (_law(label)[0], case.dim)
    if all(i == 0 for i in its):
        it = "0"
    elif any(i is None for i in its) and not any(isinstance(i, int) and i > 0 for i in its):
        it = "N/A"
    else:
        it = str(max(i for i in its if i is not None))
        unit = _COUNTERS.get(key, (None, None, None, ""))[3]
        it = f"{it} {unit}".strip()
    times = [e.time for e, *_ in evs if not math.isnan(e.time)]
    notes = sorted({e.note for e, *_ in evs if e.note})
    note = "; ".join(notes)
    if case.note:
        note = case.note + ("; " + note if note else "")
    repro = ""
    if fails:
        e, v, W, p = fails[0]
        repro = _repro(label, v, W, p)
    elif status == "DOC-ERR":
        e, v, W, p = next(x for x in evs if x[0].status == "DOC-ERR")
        repro = _repro(label, v, W, p)
    return Row("law", label, case.name, case.dim, status, max(dE) if dE else float("nan"),
               worst.residual if worst else float("nan"),
               worst.tol if worst else RESID_RTOL, it,
               float(np.median(times)) if times else float("nan"), len(evs), note[:300],
               repro)


def run_law_matrix(quick=False, labels=None, iterations=True, progress=None):
    """All law cells (a list of ``Row``)."""
    rows = []
    for case in law_cases(quick):
        for label, name, fixed in LAW_VARIANTS:
            if labels and label not in labels:
                continue
            if case.only and label not in case.only:
                continue
            rows.append(run_law_cell(label, case, iterations=iterations and
                                     (case.name != "random" or not quick)))
            if progress:
                progress(rows[-1])
    return rows
