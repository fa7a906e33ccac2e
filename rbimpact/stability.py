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
* ``dE_rel = dE / K0`` (``K0 = v.W^-1 v / 2``, the contact-space kinetic energy), with
  ``dE = P.v + P.W.P/2`` evaluated exactly (rational arithmetic) from the kernel's ``P``; for
  the laws that never create energy (smith, chatterjee_ruina, routh energetic/poisson) a
  gain ``dE > ENERGY_RTOL * E_scale`` FAILs, ``E_scale = max(K0, sum_k |P_k|(|v_k|+|v_fk|)/2)``
  (what rounding ``P`` alone can change); Routh 3D adds ``ENERGY_TOL_FACTOR * tol``. The
  note says when a gain or residual is below ``eps cond(W)`` (a cancelling formula: the
  result is exact for a nearby W, and compensated arithmetic would remove it) or above it
  (an algorithmic instability);
* the law's own residual (``law_residual``), dimensionless: how well ``v_f`` satisfies the
  law's defining equations, relative to ``s = |v| + ||W||_2 |P|`` (m/s, the size of the
  terms of ``v_f = v + W P``); FAIL above ``RESID_RTOL`` (Routh 3D:
  ``RESID_TOL_FACTOR_ROUTH3D * tol``, its integration is to ``tol``);
* iterations (``count_iterations``; 0 for closed forms) and time per kernel call.

Table columns: ``dE_rel`` (law: the largest dE/K0 of the cell; stepper: the largest energy
increase relative to max |E|), ``residual`` and ``tol`` (law: the worst residual and its
tolerance; stepper: the deepest penetration in m and its tolerance), ``iters`` (law:
iterations; stepper: impacts), ``time`` (law: median seconds per kernel call; stepper: wall
time of the run, including any compilation), ``n`` (sub-evaluations or samples).

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
RESID_RTOL = 1e-12
"""Law residual tolerance (dimensionless, relative to s = |v| + ||W||_2 |P|) for the laws
solved in closed form or by root finding to round-off (K&L, Brach, Smith, C&R, Routh 2D).
A backward-stable evaluation gives ~1e-16..1e-15; this leaves ~4500 ulps of margin."""
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
            Case("vT=1e-20", dim, _grid(vv(-1.0, 1e-20), W0, ((0.5, 0.3), (0.5, 10.0),
                                                             (1.0, 1e3))), quick=True),
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
    tags: list = field(default_factory=list)   # short failure categories


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
    from scipy.linalg import solve_triangular
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
            except NoSolutionError:
                r.append(math.inf)   # the kernel answers at tol but not at the reference
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
    ("routh", 3): ("routh_3d", (), ("nstep += 1",), "Taylor steps"),
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
    if fname not in ns or any(f not in ns for f in funcs):
        return None                          # the kernel changed: not measurable
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

    if lines and not targets:
        ns.update(saved)
        return None

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


def exact_stick_slope(W):
    """The stick slope ``kappa = 1/(W^-1)_NN = det(W)/det(W_TT)`` (1/kg) in exact rational
    arithmetic from the float entries of ``W`` (2D: ``W_NN - W_NT^2/W_TT``)."""
    F = [[Fraction(float(x)) for x in row] for row in np.asarray(W, float)]
    if len(F) == 2:
        return float(F[0][0] - F[0][1] * F[0][1] / F[1][1])
    a, b, c, d, e, f = F[0][0], F[0][1], F[0][2], F[1][1], F[1][2], F[2][2]
    det = a * (d * f - e * e) + b * (c * e - b * f) + c * (b * e - c * d)
    return float(det / (d * f - e * e))


def diagnose_no_solution(name, W):
    """Why a kernel's refusal of ``W`` is suspect (None if nothing is seen): ``W`` is
    positive definite (Cholesky succeeds) and the law's kernel documents a solution for
    every SPD ``W`` (K&L, Brach, C&R), or, for Routh, the exact stick slope is positive so
    that a Painleve-type jam would be false."""
    try:
        np.linalg.cholesky(W)
    except np.linalg.LinAlgError:
        return None
    if name in ("kane_levinson", "brach", "chatterjee_ruina"):
        return f"SPD W (cond {_cond(W):.1e}, Cholesky succeeds) rejected"
    if name == "routh":
        kappa = exact_stick_slope(W)
        if kappa > 0 and len(W) == 3 and _painleve_free(W):
            return (f"stick slope W_NN - W_TN.W_TT^-1 W_TN = {kappa:.3g} > 0 (exact) and no "
                    f"Painleve coupling: a false jam")
    return None


def _painleve_free(W):
    """No tangential direction u makes the sliding slope W_NN - mu W_NT.u vanish for any
    mu in the cases' range: |W_NT| = 0 (then a jam is impossible whatever mu)."""
    return float(np.hypot(W[0, 1], W[0, 2])) == 0.0


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
    try:
        with np.errstate(all="ignore"):
            imp = law.resolve(v, W)
    except NoSolutionError as exc:
        code = exc.mode_code
        ev.mode = code
        why = diagnose_no_solution(name, W)
        if why:
            ev.status, ev.note = "FAIL", f"NoSolutionError mode {code}: {why}"
            ev.tags = ["false jam" if "jam" in why else "SPD W rejected"]
        elif code in DOCUMENTED_ERRORS.get((name, d), ()):
            ev.status, ev.note = "DOC-ERR", f"NoSolutionError mode {code}"
            ev.tags = [f"NoSolutionError {code}"]
        else:
            ev.status = "FAIL"
            ev.note = (f"NoSolutionError mode {code}: the kernel documents a solution for "
                       f"every SPD W")
            ev.tags = [f"undocumented NoSolutionError {code}"]
        if timing:
            ev.time = _time_kernel(law, v, W, n_timing)
        return ev
    except Exception as exc:                 # undocumented exception
        ev.status, ev.note = "FAIL", f"{type(exc).__name__}: {exc}"[:200]
        ev.tags = [type(exc).__name__]
        return ev
    if timing:
        ev.time = _time_kernel(law, v, W, n_timing)
    ev.mode = imp.mode_code
    P, vf = imp.P, imp.v_f
    if not (np.all(np.isfinite(P)) and np.all(np.isfinite(vf)) and np.isfinite(imp.dE)):
        ev.status, ev.note = "FAIL", f"non-finite output P = {P.tolist()}"
        ev.tags = ["non-finite"]
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
            ev.tags.append("energy gain" + (" <eps*cond" if hint else ""))
        else:
            notes.append("gain (allowed)")
    if P[0] < 0:
        ev.status = "FAIL"
        notes.append(f"negative normal impulse P_N = {P[0]:.3g}")
        ev.tags.append("P_N < 0")
    with np.errstate(all="ignore"):
        ev.residual, ev.tol = law_residual(label, v, W, params, P, imp.mode_code, tol)
    if not ev.residual <= ev.tol:
        ev.status = "FAIL"
        hint = (" (below eps*cond(W): cancellation)"
                if ev.residual <= EPS * _cond(W) else "")
        notes.append(f"residual {ev.residual:.2g} > {ev.tol:.0e}{hint}")
        ev.tags.append("residual" + (" <eps*cond" if hint else ""))
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
    """Evaluate one (law variant, case) cell; returns a ``Row``. ``iterations``: True
    (count for every sub-evaluation), "first" (only the first: quick mode) or False."""
    evs = []
    for k, (v, W, params) in enumerate(case.subs):
        it = iterations is True or (iterations == "first" and k == 0)
        evs.append((check_impact(label, v, W, params, iterations=it,
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
    its = [e.iterations for e, *_ in evs if e.iterations is not None]
    key = (_law(label)[0], case.dim)
    if not its:
        it = "N/A"
    elif max(its) == 0:
        it = "0"
    else:
        unit = _COUNTERS.get(key, (None, None, None, ""))[3]
        it = f"{max(its)} {unit}".strip()
    times = [e.time for e, *_ in evs if not math.isnan(e.time)]
    bad = [e for e, *_ in evs if e.status != "OK"]
    if bad:
        from collections import Counter
        tags = Counter(t for e in bad for t in (e.tags or ["?"]))
        first = next(e for e in bad if e.status == status)
        note = (f"{len(bad)}/{len(evs)} {status} [" + ", ".join(
            f"{t} x{k}" for t, k in tags.most_common()) + f"]; first: {first.note}")
    else:
        note = "; ".join(sorted({e.note for e, *_ in evs if e.note}))
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
            it = iterations and ("first" if quick else True)
            rows.append(run_law_cell(label, case, iterations=it))
            if progress:
                progress(rows[-1])
    return rows


# ============================================================================================
# stepper matrix
# ============================================================================================
PEN_ATOL = 1e-9
"""Penetration tolerance (m): the stepper's own ``gap_tol`` default; a body below a plane
(or two disks/spheres overlapping) by more than ``PEN_ATOL + PEN_RTOL * L`` at a sampled
time is a missed impact. ``L`` (m) is the largest coordinate reached in the run."""
PEN_RTOL = 1e-13
"""Relative part of the penetration tolerance (round-off of positions of size L)."""
STEP_ENERGY_RTOL = 1e-9
"""Energy creation tolerance of a scene whose laws never create energy, relative to
E_ref = max |E(t)|: ``max_t (E(t) - min_{s<=t} E(s)) <= STEP_ENERGY_RTOL E_ref``, and
every impact's ``dE <= STEP_ENERGY_RTOL E_ref`` (round-off of up to 1e6 impacts ~2e-10)."""
TIME_RTOL = 1e-8
"""Reference checks of impact times (Zeno accumulation time, 1e6 elastic impacts),
relative to the reference time."""
N_SAMPLES = 200_000
"""Uniform samples per scene (quick: N_SAMPLES_QUICK), plus every event time, the midpoint
of every inter-event interval, and a bounded local minimisation of the gap around the
REFINE_MINIMA smallest sampled gaps of every body-plane pair."""
N_SAMPLES_QUICK = 20_000
REFINE_MINIMA = 12
MAX_EXTRA_SAMPLES = 2_000_000
"""Cap on event-based extra samples (events and midpoints) per scene."""

#: substrings of SimulationError messages: documented unsupported situations (DOC-ERR);
#: every other error (missed event, non-finite state, a search or solve that does not
#: converge, a stall) FAILs.
STEPPER_DOCUMENTED = ("accumulate at a single contact point", "would tip over",
                      "rolls and rocks", "needs 0 <= e <= 1", "contacts at one instant",
                      "is not supported", "Painleve")


@dataclass
class SceneCase:
    """A stepper cell: ``build()`` returns ``(simulation, t_end, max_events)``;
    ``check(result)`` returns ``(ok, note)`` for scene-specific references."""

    name: str
    case: str
    dim: int
    build: object
    never_gain: bool = True
    check: object = None
    quick: bool = True
    expect_status: str = "done"


def _sim2(scene, law, **kw):
    from .simulation import Simulation
    return Simulation(scene, law, **kw)


def _sim3(scene, law, **kw):
    from .simulation3d import Simulation3D
    return Simulation3D(scene, law, **kw)


def _zeno_case(label, dim):
    e, g, h, R = 0.99, 9.80665, 1.0, 0.05

    def build():
        law = make_law(label, dict(e=e, mu=0.3))
        t_inf = math.sqrt(2 * h / g) * (1 + e) / (1 - e)
        if dim == 2:
            from .scene import Scene2D
            from .shapes import Disk
            sc = Scene2D(gravity=(0.0, -g))
            sc.add_floor(0.0)
            sc.add_body(Disk(R), 1.0, (0.0, h + R))
            return _sim2(sc, law), t_inf + 1.0, 100_000
        from .scene3d import Scene3D
        from .shapes3d import Sphere
        sc = Scene3D(gravity=(0.0, 0.0, -g))
        sc.add_floor(0.0)
        sc.add_body(Sphere(R), 1.0, (0.0, 0.0, h + R))
        return _sim3(sc, law), t_inf + 1.0, 100_000

    def check(res):
        t1 = math.sqrt(2 * h / g)
        t_inf = t1 * (1 + e) / (1 - e)
        ev = res.events
        imp = ev[ev["kind"] == "impact"]
        ref = t1 + np.concatenate([[0.0], np.cumsum(2 * e ** np.arange(1, len(imp))
                                                    * math.sqrt(2 * g * h) / g)])
        err_t = float(np.max(np.abs(imp["t"] - ref) / ref)) if len(imp) else math.inf
        cont = ev[ev["kind"] == "contact"]
        err_inf = abs(float(cont["t"][0]) - t_inf) / t_inf if len(cont) else math.inf
        ok = err_t <= TIME_RTOL and err_inf <= TIME_RTOL and len(imp) > 1000
        return ok, (f"{len(imp)} impacts before t_inf; impact-time error {err_t:.1e}, "
                    f"t_inf error {err_inf:.1e} (tol {TIME_RTOL:.0e})")
    return SceneCase(f"{label}", "zeno_e=0.99", dim, build, check=check,
                     never_gain=label in NEVER_GAIN)


def _fast_box_case(label, dim):
    def build():
        law = make_law(label, dict(e=0.5, mu=0.5))
        if dim == 2:
            from .scene import Scene2D
            from .shapes import Box
            sc = Scene2D(gravity=(0.0, -9.81))
            sc.add_floor(0.0)
            sc.add_body(Box(0.2, 0.1), 1.0, (0.0, 1.0), angle=0.3, velocity=(3.0, -1e4),
                        angular_velocity=50.0)
            return _sim2(sc, law), 0.01, 100_000
        from .scene3d import Scene3D
        from .shapes3d import Box3D
        sc = Scene3D(gravity=(0.0, 0.0, -9.81))
        sc.add_floor(0.0)
        q = np.array([math.cos(0.15), math.sin(0.15) * 0.6, math.sin(0.15) * 0.8, 0.0])
        sc.add_body(Box3D((0.2, 0.1, 0.05)), 1.0, (0.0, 0.0, 1.0), orientation=q,
                    velocity=(3.0, -2.0, -1e4), angular_velocity=(10.0, -20.0, 50.0))
        return _sim3(sc, law), 0.01, 100_000
    return SceneCase(label, "box_at_1e4m/s", dim, build, never_gain=label in NEVER_GAIN)


def _fast_ball_case(label, dim):
    def build():
        law = make_law(label, dict(e=1.0, mu=0.3))
        if dim == 2:
            from .scene import Scene2D
            from .shapes import Disk
            sc = Scene2D(gravity=(0.0, 0.0))
            sc.add_floor(0.0)
            sc.add_plane((0.0, 1.0), (0.0, -1.0))
            sc.add_body(Disk(0.05), 1.0, (0.0, 0.5), velocity=(1.0, -1e4),
                        angular_velocity=100.0)
            return _sim2(sc, law), 0.5, 100_000
        from .scene3d import Scene3D
        from .shapes3d import Sphere
        sc = Scene3D(gravity=(0.0, 0.0, 0.0))
        sc.add_floor(0.0)
        sc.add_plane((0.0, 0.0, 1.0), (0.0, 0.0, -1.0))
        sc.add_body(Sphere(0.05), 1.0, (0.0, 0.0, 0.5), velocity=(1.0, 0.5, -1e4),
                    angular_velocity=(30.0, 100.0, 0.0))
        return _sim3(sc, law), 0.5, 100_000

    def check(res):
        n = res.n_impacts
        return n >= 4000, f"{n} impacts at 1e4 m/s between two planes 0.9 m apart"
    return SceneCase(label, "ball_at_1e4m/s", dim, build, check=check,
                     never_gain=label in NEVER_GAIN)


def _flat_box_case(label, dim, policy):
    def build():
        law = make_law(label, dict(e=0.5, mu=0.3))
        if dim == 2:
            from .scene import Scene2D
            from .shapes import Box
            sc = Scene2D(gravity=(0.0, -9.81))
            sc.add_floor(0.0)
            sc.add_body(Box(0.2, 0.1), 1.0, (0.0, 0.55))
            return _sim2(sc, law, policy=policy), 2.0, 100_000
        from .scene3d import Scene3D
        from .shapes3d import Box3D
        sc = Scene3D(gravity=(0.0, 0.0, -9.81))
        sc.add_floor(0.0)
        sc.add_body(Box3D((0.2, 0.1, 0.05)), 1.0, (0.0, 0.0, 0.525))
        return _sim3(sc, law, policy=policy), 2.0, 100_000

    def check(res):
        ev = res.events
        first = ev[ev["kind"] == "impact"][:1]
        k = int(first["cluster"][0]) if len(first) else 0
        last = ev["kind"][-1] if len(ev) else "-"
        s = res.sample([res.t_end])
        if dim == 2:
            tilt = abs(math.remainder(float(s["angle"][0, 0]), math.pi / 2))
            face = round(float(s["angle"][0, 0]) / (math.pi / 2)) % 4
        else:
            q = s["orientation"][0, 0]
            ez = _quat_rotate(q, np.array([0.0, 0.0, 1.0]))
            tilt = math.acos(min(1.0, abs(float(ez[2]))))
            face = 0 if abs(float(ez[2])) > 0.5 else 1
        tilt = max(tilt, 0.0)
        if face % 2:
            return False, (f"policy {res.policy}; the box ends standing on another face "
                           f"(angle {float(s['angle'][0, 0]) if dim == 2 else 'tilted'}), "
                           f"last event {last}")
        ok = tilt <= 1e-9 and res.policy == policy
        return ok, (f"policy {res.policy}; first cluster of {k} contacts; last event "
                    f"{last}; final tilt {tilt:.1e} rad (tol 1e-9)")
    return SceneCase(label, f"box_lands_flat_{policy}", dim, build, check=check,
                     never_gain=label in NEVER_GAIN)


def _spinning_rod_case(label, dim):
    """A rod (capsule in 3D) of length 1 m spinning at 1e4 rad/s about a horizontal axis,
    released upright so that its lower end first grazes the floor half a turn later: the
    start gap is the free-fall drop of half a turn times (1 - 1e-6). The gap dips every
    half turn (curvature 5e7 m/s^2): near misses at micrometres and a first impact with
    |v_N| ~ 1e-2 m/s against 5e3 m/s of slip."""
    w = 1e4
    g = 9.81
    gap = 0.5 * g * (math.pi / w) ** 2 * (1.0 - 1e-6)

    def build():
        law = make_law(label, dict(e=0.5, mu=0.3))
        if dim == 2:
            from .scene import Scene2D
            from .shapes import Rod
            sc = Scene2D(gravity=(0.0, -g))
            sc.add_floor(0.0)
            sc.add_body(Rod(1.0), 1.0, (0.0, 0.5 + gap), angle=math.pi / 2,
                        angular_velocity=w)
            return _sim2(sc, law), 0.05, 200_000
        from .scene3d import Scene3D
        from .shapes3d import Capsule
        sc = Scene3D(gravity=(0.0, 0.0, -g))
        sc.add_floor(0.0)
        sc.add_body(Capsule(1.0, 0.01), 1.0, (0.0, 0.0, 0.51 + gap),
                    angular_velocity=(w, 0.0, 0.0))
        return _sim3(sc, law), 0.05, 200_000

    def check(res):
        ev = res.events
        imp = ev[ev["kind"] == "impact"]
        if not len(imp):
            return False, "no impact: the grazing contact was missed"
        v0 = abs(float(imp["v_i"][0][0]))
        t0 = float(imp["t"][0])
        ok = v0 <= 0.05 and abs(t0 - math.pi / w) <= 1e-3 * math.pi / w
        vt = float(np.linalg.norm(imp["v_i"][0][1:]))
        return ok, (f"{len(imp)} impacts; first at t = {t0:.6g} s (half a turn "
                    f"{math.pi / w:.6g} s) with v_N = {-v0:.2g} m/s, |v_T| = {vt:.4g} m/s")
    return SceneCase(label, "rod_spins_1e4rad/s", dim, build, check=check,
                     never_gain=label in NEVER_GAIN)


def _million_case(label, dim, n):
    g, h, R = 9.80665, 1.0, 0.05

    def build():
        law = make_law(label, dict(e=1.0, mu=0.0))
        period = 2 * math.sqrt(2 * h / g)
        t_end = math.sqrt(2 * h / g) + (n - 0.5) * period
        if dim == 2:
            from .scene import Scene2D
            from .shapes import Disk
            sc = Scene2D(gravity=(0.0, -g))
            sc.add_floor(0.0)
            sc.add_body(Disk(R), 1.0, (0.0, h + R))
            return _sim2(sc, law), t_end, n + 10
        from .scene3d import Scene3D
        from .shapes3d import Sphere
        sc = Scene3D(gravity=(0.0, 0.0, -g))
        sc.add_floor(0.0)
        sc.add_body(Sphere(R), 1.0, (0.0, 0.0, h + R))
        return _sim3(sc, law), t_end, n + 10

    def check(res):
        imp = res.events["t"][res.events["kind"] == "impact"] if dim == 3 else \
            res._ev_t[res._ev_i[:, 0] == 0]
        t1 = math.sqrt(2 * h / g)
        ref = t1 + np.arange(len(imp)) * 2 * math.sqrt(2 * h / g)
        err = float(np.max(np.abs(imp - ref) / ref)) if len(imp) else math.inf
        ok = len(imp) == n and err <= TIME_RTOL
        return ok, f"{len(imp)} impacts (want {n}); impact-time drift {err:.1e} (tol {TIME_RTOL:.0e})"
    return SceneCase(label, f"elastic_{n:.0e}_impacts", dim, build, check=check,
                     never_gain=True)


def _galperin_case(label, dim):
    """Galperin's billiard: a disk of mass 1e6 pushes a unit disk against a wall; with
    e = 1, mu = 0 the number of collisions is 3141 (the digits of pi)."""
    def build():
        law = make_law(label, dict(e=1.0, mu=0.0))
        if dim == 2:
            from .scene import Scene2D
            from .shapes import Disk
            sc = Scene2D(gravity=(0.0, 0.0))
            sc.add_plane((0.0, 0.0), (1.0, 0.0))
            sc.add_body(Disk(0.1), 1.0, (1.0, 0.0))
            sc.add_body(Disk(0.1), 1e6, (3.0, 0.0), velocity=(-1.0, 0.0))
            return _sim2(sc, law), 10.0, 100_000
        from .scene3d import Scene3D
        from .shapes3d import Sphere
        sc = Scene3D(gravity=(0.0, 0.0, 0.0))
        sc.add_plane((0.0, 0.0, 0.0), (1.0, 0.0, 0.0))
        sc.add_body(Sphere(0.1), 1.0, (1.0, 0.0, 0.0))
        sc.add_body(Sphere(0.1), 1e6, (3.0, 0.0, 0.0), velocity=(-1.0, 0.0, 0.0))
        return _sim3(sc, law), 10.0, 100_000

    def check(res):
        n = res.n_impacts
        return n == 3141, f"{n} collisions (Galperin: 3141 for mass ratio 1e6)"
    return SceneCase(label, "billiard_mass_ratio=1e6", dim, build, check=check,
                     never_gain=True)


def _heavy_break_case(label, dim):
    """A cue disk of mass 1e6 kg breaks a triangle of three 1 kg disks between cushions,
    frictional (e = 0.95, mu = 0.2), top view without gravity."""
    def build():
        law = make_law(label, dict(e=0.95, mu=0.2))
        r = 0.03
        if dim == 2:
            from .scene import Scene2D
            from .shapes import Disk
            sc = Scene2D(gravity=(0.0, 0.0))
            for p, nrm in (((0, 0), (1, 0)), ((2, 0), (-1, 0)), ((0, 0), (0, 1)),
                           ((0, 1), (0, -1))):
                sc.add_plane(p, nrm)
            sc.add_body(Disk(r), 1e6, (0.3, 0.5), velocity=(2.0, 0.02))
            for x, y in ((1.2, 0.5), (1.3, 0.44), (1.3, 0.56)):
                sc.add_body(Disk(r), 1.0, (x, y))
            return _sim2(sc, law), 3.0, 200_000
        from .scene3d import Scene3D
        from .shapes3d import Sphere
        sc = Scene3D(gravity=(0.0, 0.0, 0.0))
        for p, nrm in (((0, 0, 0), (1, 0, 0)), ((2, 0, 0), (-1, 0, 0)),
                       ((0, 0, 0), (0, 1, 0)), ((0, 1, 0), (0, -1, 0))):
            sc.add_plane(p, nrm)
        sc.add_body(Sphere(r), 1e6, (0.3, 0.5, 0.0), velocity=(2.0, 0.02, 0.0))
        for x, y in ((1.2, 0.5), (1.3, 0.44), (1.3, 0.56)):
            sc.add_body(Sphere(r), 1.0, (x, y, 0.0))
        return _sim3(sc, law), 3.0, 200_000

    def check(res):
        return res.n_impacts > 10, f"{res.n_impacts} impacts"
    return SceneCase(label, "break_mass_ratio=1e6", dim, build, check=check,
                     never_gain=label in NEVER_GAIN)


def stepper_cases(quick=False):
    """The stepper cells (``SceneCase`` list), 2D and 3D."""
    cases = []
    for dim in (2, 3):
        for label in ("routh-energetic", "kane_levinson", "smith", "chatterjee_ruina"):
            cases.append(_zeno_case(label, dim))
        for label in ("routh-energetic", "kane_levinson"):
            cases.append(_fast_box_case(label, dim))
            cases.append(_fast_ball_case(label, dim))
            cases.append(_spinning_rod_case(label, dim))
            cases.append(_heavy_break_case(label, dim))
        for pol in ("simultaneous", "sequential"):
            cases.append(_flat_box_case("routh-energetic", dim, pol))
        n = 10_000 if quick else 1_000_000
        cases.append(_million_case("routh-energetic", dim, n))
        cases.append(_galperin_case("routh-energetic", dim))
    if quick:
        keep = {("routh-energetic", "zeno_e=0.99"), ("routh-energetic", "box_at_1e4m/s"),
                ("routh-energetic", "rod_spins_1e4rad/s"),
                ("routh-energetic", "box_lands_flat_simultaneous"),
                ("routh-energetic", "box_lands_flat_sequential"),
                ("routh-energetic", "billiard_mass_ratio=1e6")}
        cases = [c for c in cases if (c.name, c.case) in keep or c.case.startswith("elastic")]
    return cases


# ---- sampling: gaps and energy -----------------------------------------------------------
def _quat_rotate(q, v):
    """Rotate body-frame vectors ``v`` (..., 3) by unit quaternions ``q`` (..., 4)."""
    w = q[..., :1]
    u = q[..., 1:]
    t = 2.0 * np.cross(u, v)
    return v + w * t + np.cross(u, t)


def _gaps_2d(sim, s):
    """Gaps (m) of every body against every plane (lowest point of the shape) and of every
    disk pair, at the sampled states ``s`` (``Result.sample``): dict key -> array."""
    from .shapes import Disk, Ellipse, Rod
    out = {}
    bodies = sim.scene.bodies
    for b in bodies:
        i = b.index
        x, y, th = s["x"][:, i], s["y"][:, i], s["angle"][:, i]
        c, sn = np.cos(th), np.sin(th)
        for p in sim.scene.planes:
            n0, n1 = p.normal
            d = p.offset
            sh = b.shape
            if isinstance(sh, Disk) or (isinstance(sh, Ellipse) and sh.a == sh.b):
                r = sh.radius if isinstance(sh, Disk) else sh.a
                g = n0 * x + n1 * y - r - d
            elif isinstance(sh, Ellipse):
                nb0 = c * n0 + sn * n1
                nb1 = -sn * n0 + c * n1
                g = n0 * x + n1 * y - np.sqrt(sh.a ** 2 * nb0 ** 2 + sh.b ** 2 * nb1 ** 2) - d
            else:
                V = np.asarray(sh.vertices)
                rad = sh.radius if isinstance(sh, Rod) else 0.0
                wx = c[:, None] * V[None, :, 0] - sn[:, None] * V[None, :, 1]
                wy = sn[:, None] * V[None, :, 0] + c[:, None] * V[None, :, 1]
                g = np.min(n0 * (x[:, None] + wx) + n1 * (y[:, None] + wy), axis=1) - rad - d
            out[(i, "plane", p.index)] = g
    disks = [b for b in bodies if isinstance(b.shape, Disk)]
    for a in range(len(disks)):
        for bb in range(a + 1, len(disks)):
            i, j = disks[a].index, disks[bb].index
            dist = np.hypot(s["x"][:, i] - s["x"][:, j], s["y"][:, i] - s["y"][:, j])
            out[(i, "body", j)] = dist - disks[a].shape.radius - disks[bb].shape.radius
    return out


def _gaps_3d(sim, s):
    from .shapes3d import Box3D, Sphere
    out = {}
    bodies = sim.scene.bodies
    pos, q = s["position"], s["orientation"]
    for b in bodies:
        i = b.index
        sh = b.shape
        if isinstance(sh, Sphere):
            pts, rad = pos[:, i, None, :], sh.radius
        else:
            if isinstance(sh, Box3D):
                V, rad = sh.vertices, 0.0
            else:
                V, rad = np.array([[0, 0, -0.5 * sh.length], [0, 0, 0.5 * sh.length]]), \
                    sh.radius
            qq = np.repeat(q[:, i, None, :], len(V), axis=1)
            pts = pos[:, i, None, :] + _quat_rotate(qq, np.broadcast_to(V, qq.shape[:2] + (3,)))
        for p in sim.scene.planes:
            n = np.asarray(p.normal)
            out[(i, "plane", p.index)] = np.min(pts @ n, axis=1) - rad - p.offset
    sph = [b for b in bodies if isinstance(b.shape, Sphere)]
    for a in range(len(sph)):
        for bb in range(a + 1, len(sph)):
            i, j = sph[a].index, sph[bb].index
            dist = np.linalg.norm(pos[:, i] - pos[:, j], axis=1)
            out[(i, "body", j)] = dist - sph[a].shape.radius - sph[bb].shape.radius
    return out


def kinetic_from_sample(res, s, dim):
    """Kinetic energy (J) of the sampled states ``s`` (``Result.sample``), per sample."""
    if dim == 2:
        return np.sum(0.5 * res.masses * (s["vx"] ** 2 + s["vy"] ** 2)
                      + 0.5 * res.moments * s["omega"] ** 2, axis=1)
    q = s["orientation"]
    wb = _quat_rotate(q * np.array([1.0, -1.0, -1.0, -1.0]), s["angular_velocity"])
    return np.sum(0.5 * res.masses * np.sum(s["velocity"] ** 2, axis=-1)
                  + 0.5 * np.sum(res.inertias[None] * wb * wb, axis=-1), axis=1)


def _energy_from_sample(res, s, dim):
    """Kinetic plus gravitational energy (J) of the sampled states, per sample."""
    if dim == 2:
        g = res.gravity
        pot = -np.sum(res.masses * (g[0] * s["x"] + g[1] * s["y"]), axis=1)
    else:
        pot = -np.sum(res.masses * (s["position"] @ res.gravity), axis=1)
    return kinetic_from_sample(res, s, dim) + pot


def _scale_length(s, dim):
    if dim == 2:
        return float(max(np.abs(s["x"]).max(), np.abs(s["y"]).max(), 1.0))
    return float(max(np.abs(s["position"]).max(), 1.0))


def _sample_times(res, n):
    t0, t1 = res.t_start, res.t_end
    ev = np.asarray(res._ev_t if hasattr(res, "_ev_t") else res.events["t"])
    extra = ev[: MAX_EXTRA_SAMPLES // 2]
    mids = 0.5 * (extra[1:] + extra[:-1])
    t = np.concatenate([np.linspace(t0, t1, n), extra, mids])
    return np.unique(np.clip(t, t0, t1))


def refine_minima(t, g, gap_at, n_minima):
    """The smallest of the sampled gaps ``g`` (m, at the sorted times ``t``) and of the
    bottoms of its ``n_minima`` smallest local minima, each refined by a bounded
    minimisation of ``gap_at(time)`` between the neighbouring samples (the sampled minimum
    of a smooth dip can miss its true bottom)."""
    from scipy.optimize import minimize_scalar
    best = float(g.min())
    loc = np.where((g[1:-1] <= g[:-2]) & (g[1:-1] <= g[2:]))[0] + 1
    for k in loc[np.argsort(g[loc])][:n_minima]:
        lo, hi = t[k - 1], t[k + 1]
        if hi > lo:
            r = minimize_scalar(gap_at, bounds=(lo, hi), method="bounded",
                                options={"xatol": 1e-15 * max(1.0, abs(hi))})
            best = min(best, float(r.fun))
    return best


def _refine(res, sim, dim, key, t, g):
    """One body-plane gap (``key``) refined around its REFINE_MINIMA smallest sampled local
    minima (``refine_minima``)."""
    def gap(tt):
        return float((_gaps_2d if dim == 2 else _gaps_3d)(sim, res.sample([tt]))[key][0])
    return refine_minima(t, g, gap, REFINE_MINIMA)


def run_scene(sc, quick=False):
    """Run one stepper cell; returns a ``Row``."""
    t0 = time.perf_counter()
    note = []
    try:
        sim, t_end, max_events = sc.build()
    except Exception as exc:
        return Row("stepper", sc.name, sc.case, sc.dim, "NOT-RUN", math.nan, math.nan,
                   math.nan, "-", time.perf_counter() - t0, 1,
                   f"scene not built: {type(exc).__name__}: {exc}"[:300])
    status = "OK"
    try:
        import warnings
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            res = sim.run(t_end, max_events=max_events)
    except NoSolutionError as exc:
        res = getattr(exc, "result", None)
        status = "DOC-ERR"
        note.append(f"NoSolutionError: {exc}"[:200])
    except SimulationError as exc:
        res = getattr(exc, "result", None)
        msg = str(exc)
        status = "DOC-ERR" if any(m in msg for m in STEPPER_DOCUMENTED) else "FAIL"
        note.append(f"SimulationError: {msg}"[:240])
    except Exception as exc:
        return Row("stepper", sc.name, sc.case, sc.dim, "FAIL", math.nan, math.nan,
                   math.nan, "-", time.perf_counter() - t0, 1,
                   f"{type(exc).__name__}: {exc}"[:300])
    wall = time.perf_counter() - t0
    if res is None or res.t_end <= res.t_start:
        return Row("stepper", sc.name, sc.case, sc.dim, status, math.nan, math.nan,
                   math.nan, "-", wall, 1, "; ".join(note))
    if status == "OK" and res.status != sc.expect_status:
        status = "FAIL"
        note.append(f"status {res.status!r} (expected {sc.expect_status!r})")
    n = N_SAMPLES_QUICK if quick else N_SAMPLES
    t = _sample_times(res, n)
    s = res.sample(t)
    gaps = (_gaps_2d if sc.dim == 2 else _gaps_3d)(sim, s)
    L = _scale_length(s, sc.dim)
    pen_tol = PEN_ATOL + PEN_RTOL * L
    worst = 0.0
    for key, g in gaps.items():
        gmin = _refine(res, sim, sc.dim, key, t, g)
        worst = max(worst, -gmin)
    if worst > pen_tol:
        status = "FAIL"
        note.append(f"penetration {worst:.3g} m > {pen_tol:.1g} m (missed impact)")
    E = _energy_from_sample(res, s, sc.dim)
    Eref = float(np.max(np.abs(E))) or 1.0
    gain = float(np.max(E - np.minimum.accumulate(E))) / Eref
    ev = res.events
    imp = ev[ev["kind"] == "impact"]
    ev_gain = 0.0
    if len(imp):   # a joint solve's per-contact dE may be > 0: sum each instant's cluster
        tt, inv = np.unique(imp["t"], return_inverse=True)
        ev_gain = max(float(np.bincount(inv, weights=imp["dE"]).max()), 0.0) / Eref
    dE_rel = max(gain, ev_gain)
    if sc.never_gain and dE_rel > STEP_ENERGY_RTOL:
        if status != "DOC-ERR":
            status = "FAIL"
        note.append(f"energy created: {dE_rel:.2g} E_ref > {STEP_ENERGY_RTOL:.0e}")
    if sc.check is not None and status in ("OK", "FAIL") and res.status == "done":
        ok, text = sc.check(res)
        note.append(text)
        if not ok:
            status = "FAIL"
    return Row("stepper", sc.name, sc.case, sc.dim, status, dE_rel, worst, pen_tol,
               str(res.n_impacts), wall, len(t), "; ".join(note)[:400])


def run_stepper_matrix(quick=False, progress=None):
    rows = []
    for sc in stepper_cases(quick):
        rows.append(run_scene(sc, quick))
        if progress:
            progress(rows[-1])
    return rows


# ============================================================================================
# report
# ============================================================================================
NOTE_WIDTH = 110
"""Characters of the note shown per table row (the CSV keeps the full note and the
reproducer)."""


def format_table(rows):
    """The terminal table: one line per row, then nothing else (see ``summary``)."""
    head = ["kind", "law/scene", "case", "dim", "status", "dE_rel", "residual", "tol",
            "iters", "time", "n", "note"]
    body = []
    for r in rows:
        f = r.fields()
        body.append([str(x) for x in f[:11]] + [r.note[:NOTE_WIDTH]])
    widths = [max(len(head[k]), *(len(b[k]) for b in body)) if body else len(head[k])
              for k in range(11)]

    def line(cells):
        return "  ".join(c.ljust(widths[k]) if k < 11 else c for k, c in enumerate(cells))
    out = [line(head), line(["-" * w for w in widths] + ["-" * 4])]
    out += [line(b) for b in body]
    return "\n".join(out)


def summary(rows, elapsed=None):
    """One line: counts per status and the verdict."""
    counts = {k: sum(r.status == k for r in rows) for k in ("OK", "DOC-ERR", "FAIL",
                                                             "NOT-RUN")}
    verdict = "ok" if counts["FAIL"] == 0 else "FAILED"
    t = f" in {elapsed:.1f} s" if elapsed is not None else ""
    return (f"stability: {len(rows)} cells{t}: {counts['OK']} OK, {counts['DOC-ERR']} "
            f"documented errors, {counts['FAIL']} FAIL, {counts['NOT-RUN']} not run -> "
            f"{verdict}")


def write_csv(rows, path):
    """Write the rows (all fields, full notes and reproducers) to ``path``."""
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(FIELDS)
        for r in rows:
            w.writerow(r.fields())


def stability_report(quick=False, out=None, progress=None):
    """Run the stability matrices; returns ``(text, rows, ok)``.

    ``quick``: the subset for tests and CI (well under a minute with compiled kernels);
    ``out``: a CSV path for the rows; ``progress``: optional callable receiving each
    ``Row`` as it completes. ``text`` is the table plus the summary line, ``ok`` is False
    when any cell FAILs."""
    t0 = time.perf_counter()
    rows = run_law_matrix(quick=quick, progress=progress)
    rows += run_stepper_matrix(quick=quick, progress=progress)
    text = format_table(rows) + "\n" + summary(rows, time.perf_counter() - t0)
    if out:
        write_csv(rows, out)
    ok = not any(r.status == "FAIL" for r in rows)
    return text, rows, ok


def main(argv=None):
    """``python -m rbimpact.stability [--quick] [--out report.csv]``: print the table and
    return the exit status (1 when a cell FAILs)."""
    import argparse
    ap = argparse.ArgumentParser(prog="rbimpact stability", description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="the fast subset (tests, CI)")
    ap.add_argument("--out", metavar="CSV", help="write every row to this CSV file")
    args = ap.parse_args(argv)
    text, rows, ok = stability_report(quick=args.quick, out=args.out)
    print(text)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
