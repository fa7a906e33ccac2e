"""The impulse-space picture of one contact: what each law can reach, and where it creates energy.

After Chatterjee & Ruina (1998) and the seed paper's last figure. Conventions (DESIGN §3):
contact-space vectors are normal first, ``v`` (m/s) is the velocity of A's contact point
minus B's (``v_N < 0`` approaches), ``P`` (N s) is the impulse on A, ``W`` (1/kg) the
Delassus matrix, ``v_f = v + W P`` and the kinetic energy change is

    dE(P) = P . v + P . W P / 2  = P . (v + v_f) / 2        (J).

``dE(P) <= 0`` (no energy created) is a filled ellipse centred on ``P_II = -W^-1 v``
(plastic sticking impact, the most dissipative impulse: ``dE(P_II) = -v . W^-1 v / 2``)
whose boundary ``dE = 0`` passes through ``0`` and ``2 P_II``. ``P_I = (-v_N / W_NN, 0)``
is the plastic frictionless impulse; the friction cone is ``|P_T| <= mu P_N``.

3D contacts are shown in their *plane of interest*, spanned by the normal and the initial
tangential slip direction ``t = v_T / |v_T|`` (if ``v_T = 0``: the tangential direction of
``P_II``; if that is zero too: the first tangent axis ``T1``). Plane coordinates are
``(P_N, P . t)``. Impulses with a component out of the plane are projected onto it; the
ellipse drawn is the *shadow* of the 3D no-energy-creation ellipsoid on the plane (every
impulse that creates no energy projects inside it; its rim is the projection of 3D
impulses with ``dE = 0``, kept in ``ellipse_full``). The projected cone is the same wedge
``|P_T| <= mu P_N``. Energy flags always use the full 3D ``dE``.

``import rbimpact.impulse_space`` does not import matplotlib; ``ImpulseSpace.plot`` does.
"""
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np

from .laws import LAWS, RESTITUTION_KINDS, Law, MODE_NAMES, _check_contact

__all__ = ["impulse_space", "ImpulseSpace", "Reach", "energy_change", "impulse_space_report",
           "DEFAULT_LAWS", "CURVE_LAWS", "REGION_LAWS"]

DEFAULT_LAWS = ("kane_levinson", "smith", "routh", "brach", "chatterjee_ruina")
#: laws with one free parameter e (a curve in impulse space) and their default e range
CURVE_LAWS = ("kane_levinson", "smith", "routh")
#: laws with two free parameters e, e_t (a region in impulse space)
REGION_LAWS = ("brach", "chatterjee_ruina")

# plot styles: colour per law, line style per Routh restitution kind
_COLOURS = {"kane_levinson": "tab:orange", "smith": "tab:green", "routh": "tab:blue",
            "brach": "tab:purple", "chatterjee_ruina": "tab:brown"}
_ROUTH_STYLE = {"energetic": "-", "poisson": "--", "newton": ":"}
_NAMES = {"kane_levinson": "Kane & Levinson", "smith": "Smith", "routh": "Routh",
          "brach": "Brach", "chatterjee_ruina": "Chatterjee & Ruina"}


def energy_change(P, v, W):
    """Kinetic energy change ``dE = P . v + P . W P / 2`` (J) for impulses ``P`` (..., d) N s,
    pre-impact relative velocity ``v`` (d,) m/s and Delassus matrix ``W`` (d, d) 1/kg.
    Equal to ``P . (v + v_f) / 2`` with ``v_f = v + W P``; negative means dissipated."""
    P = np.asarray(P, dtype=np.float64)
    return P @ np.asarray(v, dtype=np.float64) + 0.5 * np.einsum("...i,ij,...j->...", P, W, P)


@dataclass(frozen=True, eq=False, repr=False)
class Reach:
    """The impulses one law reaches as its free parameters vary (fixed ``mu``).

    - ``key``: the entry's name in ``ImpulseSpace.reach`` ("routh" is Routh with energetic
      restitution, the law's default; "routh:poisson", "routh:newton" the other kinds).
    - ``law``: registry name; ``label``: display name; ``kind``: "curve" (parameter ``e``)
      or "region" (parameters ``e`` and ``e_t``); ``fixed``: the fixed parameters
      (``mu``, Routh's ``restitution``); ``ranges``: ``{"e": (lo, hi)[, "e_t": (lo, hi)]}``.
    - ``params``: ``{"e": (m,)[, "e_t": (m,)]}`` parameter values of the m solved points,
      in sampling order (curve: e increasing; region: an e-major grid, failed points removed).
    - ``P`` (m, 2): impulses in plane coordinates ``(P_N, P_T)`` (N s); ``P_full`` (m, d)
      in contact space; ``v_f`` (m, d) m/s; ``dE`` (m,) J; ``mode`` (m,) kernel mode codes.
    - ``energy_gain`` (m,) bool: the law created kinetic energy beyond round-off
      (``Law.resolve_batch``'s flag).
    - ``outline`` (k, 2) / ``outline_full`` (k, d): regions only (``None`` for curves):
      the region's boundary polygon (closed): for each e (about n/2 values), the solved
      impulse with the smallest plane P_T over the e_t samples, then, e decreasing, the
      largest. Exact in 2D (each e maps onto a segment of the line of constant v_fN);
      in 3D the envelope of the projected points.
    - ``failed``: ``{"e": ..., ["e_t": ...,] "mode": ...}`` parameters for which the law
      has no solution (or did not converge); they are kept out of every other array.
    """

    key: str
    law: str
    label: str
    kind: str
    fixed: MappingProxyType
    ranges: MappingProxyType
    params: MappingProxyType
    P: np.ndarray
    P_full: np.ndarray
    v_f: np.ndarray
    dE: np.ndarray
    mode: np.ndarray
    energy_gain: np.ndarray
    outline: np.ndarray = None
    outline_full: np.ndarray = None
    failed: MappingProxyType = field(default_factory=lambda: MappingProxyType({}))

    def __repr__(self):
        return (f"Reach({self.key!r}, {self.kind}, {self.P.shape[0]} points, "
                f"{int(self.energy_gain.sum())} creating energy, {self.n_failed} failed)")

    @property
    def mode_names(self):
        """Final mode name of every solved point ("stick", "slip", ...)."""
        return [MODE_NAMES[int(m)][0] for m in self.mode]

    @property
    def n_failed(self):
        """Number of parameter samples with no solution."""
        return int(len(self.failed.get("e", ())))

    def at(self, e, e_t=None):
        """Index of the solved sample nearest to parameters ``(e[, e_t])`` (exact on grid
        values such as e = 0, 1 and e_t = -1, 0, 1)."""
        d = (self.params["e"] - e) ** 2
        if self.kind == "region":
            d = d + (self.params["e_t"] - (0.0 if e_t is None else e_t)) ** 2
        return int(np.argmin(d))


@dataclass(frozen=True, eq=False, repr=False)
class ImpulseSpace:
    """Impulse space of one contact (result of ``impulse_space``); all arrays, no NaN.

    Plane coordinates are ``(P_N, P_T)`` in N s (2D: the contact's own; 3D: see the
    module docstring). Attributes:

    - ``v`` (d,) m/s, ``W`` (d, d) 1/kg, ``mu``: the contact; ``dim`` = d.
    - ``basis`` (d, 2): columns are the plane's unit vectors in contact space
      (``P_full = basis @ P_plane`` for in-plane impulses); 2D: the identity.
    - ``P_I``, ``P_II`` (2,): plastic frictionless and plastic sticking impulses
      (``P_I_full``, ``P_II_full`` (d,) in contact space).
    - ``dE_min``: ``dE(P_II) = -v . W^-1 v / 2`` (J), the most energy any impulse removes.
    - ``ellipse`` (n, 2): samples of the boundary ``dE = 0`` (through 0 and 2 P_II; sample
      0 is P = 0, sample n/2 is 2 P_II when n is even); ``ellipse_full`` (n, d) the
      contact-space impulses they come from (``dE = 0`` exactly up to round-off).
    - ``cone`` (3, 2): the friction cone's boundary as a polyline
      ``[upper ray end, apex 0, lower ray end]`` (``P_T = +mu P_N`` then ``-mu P_N``),
      clipped to ``extent``.
    - ``extent``: ``((P_N_lo, P_N_hi), (P_T_lo, P_T_hi))`` (N s) covering everything.
    - ``reach``: ``{key: Reach}`` per law (see ``Reach``), in the order requested.
    """

    v: np.ndarray
    W: np.ndarray
    mu: float
    dim: int
    basis: np.ndarray
    P_I: np.ndarray
    P_II: np.ndarray
    P_I_full: np.ndarray
    P_II_full: np.ndarray
    dE_min: float
    ellipse: np.ndarray
    ellipse_full: np.ndarray
    cone: np.ndarray
    extent: tuple
    reach: MappingProxyType

    def __getitem__(self, key):
        return self.reach[key]

    def __repr__(self):
        return (f"ImpulseSpace(v={_fmt(self.v)}, W={_fmt_W(self.W)}, mu={self.mu:g}, "
                f"reach=[{', '.join(self.reach)}])")

    def dE(self, P_full):
        """Exact kinetic energy change (J) of contact-space impulses ``P_full`` (..., d)."""
        return energy_change(P_full, self.v, self.W)

    def summary(self):
        """A compact text summary: P_I, P_II and, per law, reachable range and energy."""
        return _summary(self)

    def plot(self, path=None, *, ax=None, show_grid_points=False):
        """Draw the picture in the (P_T, P_N) plane (P_T horizontal, P_N vertical, N s).

        Ellipse ``dE = 0`` (black), friction cone (dashed), ``P_I`` and ``P_II`` (markers),
        each law in its own colour (curves as lines, Routh's restitution kinds as line
        styles; regions as a light fill inside their outline, optionally with their grid
        points), points that create energy as red crosses (one artist). Saves a PNG (or
        any format matplotlib infers from the suffix) to ``path`` if given; a new figure
        is drawn on the Agg canvas (no pyplot, no GUI). Returns the matplotlib ``Figure``.

        Artists added to the axes: lines (``ax.lines``): ellipse, cone, P_I, P_II, 2 P_II,
        one per curve, one outline per region; collections (``ax.collections``): one for
        the energy-creating points if there are any, plus one per region (its grid points)
        when ``show_grid_points``; patches (``ax.patches``): the fills of the ellipse and
        of each region.
        """
        return _plot(self, path, ax=ax, show_grid_points=show_grid_points)


# ---------------------------------------------------------------------------------------------
# geometry

def _plane_basis(v, W):
    """Orthonormal contact-space frame Q (d, d) whose first two columns span the plane of
    interest: the normal and the initial slip direction (fallbacks in the module doc)."""
    d = v.shape[0]
    if d == 2:
        return np.eye(2)
    t = v[1:].copy()
    if np.hypot(t[0], t[1]) <= 1e-14 * max(abs(v[0]), 1e-300):
        t = -np.linalg.solve(W, v)[1:]               # tangential part of P_II
        if np.hypot(t[0], t[1]) <= 1e-14 * np.abs(np.linalg.solve(W, v)).max():
            t = np.array([1.0, 0.0])
    t = t / np.hypot(t[0], t[1])
    Q = np.zeros((3, 3))
    Q[0, 0] = 1.0
    Q[1:, 1] = t
    Q[1:, 2] = (-t[1], t[0])
    return Q


def _ellipse(v, W, Q, n):
    """Boundary of the (shadow of the) set dE <= 0 in the plane: plane samples (n, 2) and
    the contact-space impulses (n, d) with dE = 0 that project onto them."""
    d = v.shape[0]
    Wq = Q.T @ W @ Q                                  # W in the frame Q
    vq = Q.T @ v                                      # (v_N, |v_T|[, 0])
    Wp = np.linalg.inv(np.linalg.inv(Wq)[:2, :2])     # Schur complement: effective plane W
    vp = vq[:2]
    P_II = -np.linalg.solve(Wp, vp)
    rho = np.sqrt(vp @ np.linalg.solve(Wp, vp))       # sqrt(v . W^-1 v) = sqrt(-2 dE_min)
    L = np.linalg.cholesky(Wp)                        # Wp = L L^T;  P = P_II + L^-T y, |y| = rho
    y0 = -L.T @ P_II                                  # y of P = 0: start the samples there
    th = np.arctan2(y0[1], y0[0]) + 2.0 * np.pi * np.arange(n) / n
    y = rho * np.stack([np.cos(th), np.sin(th)], axis=1)
    pts = P_II + np.linalg.solve(L.T, y.T).T
    pts[0] = 0.0                                      # exact, free of round-off
    if n % 2 == 0:
        pts[n // 2] = 2.0 * P_II
    if d == 2:
        return pts, pts.copy()
    s = -(pts @ Wq[2, :2]) / Wq[2, 2]                 # out-of-plane component minimising dE
    full = np.column_stack([pts, s]) @ Q.T
    return pts, full


def _cone(mu, extent):
    (nlo, nhi), (tlo, thi) = extent
    if mu == 0.0:
        return np.array([[nhi, 0.0], [0.0, 0.0], [nhi, 0.0]])
    up = min(nhi, thi / mu)
    lo = min(nhi, -tlo / mu)
    return np.array([[up, mu * up], [0.0, 0.0], [lo, -mu * lo]])


# ---------------------------------------------------------------------------------------------
# law sampling

def _solve(law, v, W, params):
    """Batch-solve one contact for many parameter sets; returns (BatchImpact, ok mask)."""
    m = len(next(iter(params.values())))
    V = np.broadcast_to(v, (m, v.shape[0]))
    WW = np.broadcast_to(W, (m,) + W.shape)
    res = law.resolve_batch(V, WW, on_failure="flag", validate=False, **params)
    ok = res.mode >= 0
    ok &= np.isfinite(res.P).all(axis=1) & np.isfinite(res.dE)
    return res, ok


def _outline(law, v, W, Q, rng, m_e, m_t):
    """Outline of a region law's reach: for each of m_e values of e, the solved impulses
    over m_t values of e_t, and their extremes in plane P_T; the polygon runs through the
    minima (e increasing) then the maxima (e decreasing) and is closed. Both region laws
    keep v_fN = -e v_N in every branch, so in 2D each e maps onto one line
    W_N . P = -(1 + e) v_N, its image is a segment of that line (clipped at the cone),
    and the polygon is the region's boundary. 3D: the same on the projected points."""
    E, ET = np.meshgrid(np.linspace(*rng["e"], m_e), np.linspace(*rng["e_t"], m_t),
                        indexing="ij")
    res, ok = _solve(law, v, W, {"e": E.ravel(), "e_t": ET.ravel()})
    P = res.P.reshape(m_e, m_t, -1)
    ok = ok.reshape(m_e, m_t)
    lo, hi = [], []
    for i in range(m_e):
        if not ok[i].any():
            continue
        Pi = P[i][ok[i]]
        t = Pi @ Q[:, 1]
        lo.append(Pi[np.argmin(t)])
        hi.append(Pi[np.argmax(t)])
    if not lo:
        return np.zeros((0, v.shape[0]))
    return np.array(lo + hi[::-1] + lo[:1])


def _law_ranges(name, ranges):
    spec = LAWS[name].params
    out = {"e": (0.0, 1.0) if name in CURVE_LAWS else (spec["e"].lo, spec["e"].hi)}
    if name in REGION_LAWS:
        out["e_t"] = (spec["e_t"].lo, spec["e_t"].hi)
    for k, (lo, hi) in (ranges or {}).get(name, {}).items():
        if k not in out:
            raise ValueError(f"ranges[{name!r}]: law {name!r} has no free parameter {k!r} "
                             f"here (free: {', '.join(out)})")
        if not (spec[k].lo <= lo <= hi <= spec[k].hi):
            raise ValueError(f"ranges[{name!r}][{k!r}] = ({lo}, {hi}) must lie within the "
                             f"law's range [{spec[k].lo:g}, {spec[k].hi:g}] with lo <= hi")
        out[k] = (float(lo), float(hi))
    return out


def _reach(key, name, fixed, rng, v, W, Q, n, n_grid):
    law = Law(name, e=rng["e"][0], **fixed)
    project = Q[:, :2].T
    if name in CURVE_LAWS:
        kind = "curve"
        grid = {"e": np.linspace(*rng["e"], n)}
    else:
        kind = "region"
        E, ET = np.meshgrid(np.linspace(*rng["e"], n_grid), np.linspace(*rng["e_t"], n_grid),
                            indexing="ij")
        grid = {"e": E.ravel(), "e_t": ET.ravel()}
    res, ok = _solve(law, v, W, grid)
    outline = outline_full = None
    if kind == "region":
        outline_full = _outline(law, v, W, Q, rng, max(n // 2, 8), n_grid)
        outline = outline_full @ project.T
    label = _NAMES[name]
    if name == "routh":
        label += f" ({fixed['restitution']})"
    failed = {k: x[~ok] for k, x in grid.items()}
    failed["mode"] = res.mode[~ok]
    P_full = res.P[ok]
    return Reach(
        key=key, law=name, label=label, kind=kind, fixed=MappingProxyType(dict(fixed)),
        ranges=MappingProxyType(rng), params=MappingProxyType({k: x[ok] for k, x in grid.items()}),
        P=P_full @ project.T, P_full=P_full, v_f=res.v_f[ok], dE=res.dE[ok],
        mode=res.mode[ok], energy_gain=res.energy_gain[ok], outline=outline,
        outline_full=outline_full, failed=MappingProxyType(failed))


def impulse_space(v, W, mu, laws=DEFAULT_LAWS, n=200, *, n_grid=41,
                  routh_restitution=RESTITUTION_KINDS, ranges=None):
    """Impulse space of one contact: energy ellipse, friction cone, P_I, P_II and what each
    law reaches as its free parameters vary. Returns an ``ImpulseSpace``.

    ``v`` (d,) m/s and ``W`` (d, d) 1/kg, d = 2 or 3 (3D: plane of interest, module doc);
    ``v_N < 0`` is required (an impact). ``mu`` >= 0 is fixed. ``laws``: registry names.
    ``n``: samples of the ellipse and of each curve (e over [0, 1] for Kane & Levinson,
    Smith and Routh). Regions (Brach: e in [-1, 1], e_t in [-1, 1]; Chatterjee & Ruina:
    e in [0, 1], e_t in [-1, 1]) are sampled on an ``n_grid`` x ``n_grid`` grid, their
    outline with about ``n`` points. ``routh_restitution``: Routh's termination kinds,
    one curve each (keys "routh" for energetic, "routh:poisson", "routh:newton").
    ``ranges``: optional narrower parameter ranges, e.g. ``{"brach": {"e": (0, 1)}}``.
    Parameter samples where a law has no solution are left out and listed in
    ``Reach.failed``; no output array contains NaN.
    """
    v, W = _check_contact(v, W)
    if not v[0] < 0.0:
        raise ValueError(f"no impact: v_N = {v[0]!r} >= 0 (separating), every law gives P = 0; "
                         "impulse space needs an approaching contact (v_N < 0)")
    mu = float(mu)
    if not (np.isfinite(mu) and mu >= 0.0):
        raise ValueError(f"mu must be finite and >= 0, got {mu!r}")
    n, n_grid = int(n), int(n_grid)
    if n < 8 or n_grid < 2:
        raise ValueError(f"need n >= 8 and n_grid >= 2, got n = {n}, n_grid = {n_grid}")
    if isinstance(laws, str):
        laws = (laws,)
    for name in laws:
        if name not in LAWS:
            raise ValueError(f"unknown law {name!r}; known laws: {', '.join(LAWS)}")
    if isinstance(routh_restitution, str):
        routh_restitution = (routh_restitution,)
    for kind in routh_restitution:
        if kind not in RESTITUTION_KINDS:
            raise ValueError(f"routh_restitution: {kind!r} is not one of {RESTITUTION_KINDS}")
    for name in (ranges or {}):
        if name not in laws:
            raise ValueError(f"ranges given for {name!r}, which is not among laws {tuple(laws)}")

    Q = _plane_basis(v, W)
    basis = Q[:, :2].copy()
    P_II_full = -np.linalg.solve(W, v)
    P_I_full = np.zeros_like(v)
    P_I_full[0] = -v[0] / W[0, 0]
    ellipse, ellipse_full = _ellipse(v, W, Q, n)

    reach = {}
    for name in laws:
        rng = _law_ranges(name, ranges)
        if name == "routh":
            for kind in routh_restitution:
                key = "routh" if kind == "energetic" else f"routh:{kind}"
                reach[key] = _reach(key, name, {"mu": mu, "restitution": kind}, rng,
                                    v, W, Q, n, n_grid)
        else:
            reach[name] = _reach(name, name, {"mu": mu}, rng, v, W, Q, n, n_grid)

    pts = [ellipse, (P_I_full @ basis)[None], np.zeros((1, 2))]
    for r in reach.values():
        pts.append(r.P)
        if r.outline is not None:
            pts.append(r.outline)
    pts = np.concatenate(pts)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    pad = 0.08 * max(hi - lo)
    extent = ((lo[0] - pad, hi[0] + pad), (lo[1] - pad, hi[1] + pad))
    return ImpulseSpace(
        v=v, W=W, mu=mu, dim=v.shape[0], basis=basis, P_I=P_I_full @ basis,
        P_II=P_II_full @ basis, P_I_full=P_I_full, P_II_full=P_II_full,
        dE_min=float(energy_change(P_II_full, v, W)), ellipse=ellipse, ellipse_full=ellipse_full,
        cone=_cone(mu, extent), extent=extent, reach=MappingProxyType(reach))


# ---------------------------------------------------------------------------------------------
# text

def _fmt(x):
    return "(" + ", ".join(f"{float(a):.6g}" for a in np.ravel(x)) + ")"


def _fmt_W(W):
    return "[" + ", ".join(_fmt(row).replace("(", "[").replace(")", "]") for row in W) + "]"


def _runs(mask, values):
    """Contiguous runs of True in mask, as 'lo..hi' strings of values."""
    out, start = [], None
    for i, m in enumerate(np.append(mask, False)):
        if m and start is None:
            start = i
        elif not m and start is not None:
            a, b = values[start], values[i - 1]
            out.append(f"{a:.3g}" if a == b else f"{a:.3g}..{b:.3g}")
            start = None
    return ", ".join(out)


def _summary(s):
    lines = [
        "Impulse space of one contact (normal first; P = impulse on A, N s; dE in J)",
        f"  v = {_fmt(s.v)} m/s, W = {_fmt_W(s.W)} 1/kg, "
        f"mu = {s.mu:g}",
    ]
    if s.dim == 3:
        lines.append(f"  3D: plane of interest spanned by n and t = {_fmt(s.basis[1:, 1])} "
                     "(initial slip); in-plane coordinates (P_N, P.t), projected")
    lines += [
        f"  P_I  = {_fmt(s.P_I)}  plastic, frictionless (-v_N/W_NN along n)",
        f"  P_II = {_fmt(s.P_II)}  plastic, sticking (-W^-1 v): dE = {s.dE_min:.6g}, the minimum",
        f"  energy ellipse dE(P) = 0 through 0 and 2 P_II = {_fmt(2 * s.P_II)}; "
        f"friction cone |P_T| <= {s.mu:g} P_N",
        "",
        f"  {'law':<28} {'P_N range':<20} {'P_T range':<22} {'P (e=1, e_t=0)':<22} energy created",
    ]
    for r in s.reach.values():
        name = r.label
        if r.P.shape[0] == 0:
            lines.append(f"  {name:<28} no solution for any parameter ({r.n_failed} failed)")
            continue
        pn = f"[{r.P[:, 0].min():.4g}, {r.P[:, 0].max():.4g}]"
        pt = f"[{r.P[:, 1].min():.4g}, {r.P[:, 1].max():.4g}]"
        i = r.at(1.0, 0.0)
        ok_ref = abs(r.params["e"][i] - 1.0) < 1e-12 and (
            r.kind == "curve" or abs(r.params["e_t"][i]) < 1e-12)
        ref = _fmt(r.P[i]) if ok_ref else "(no solution)"
        g = r.energy_gain
        if not g.any():
            en = f"no (max dE = {r.dE.max():.3g})"
        else:
            j = int(np.argmax(np.where(g, r.dE, -np.inf)))
            where = (f"e = {r.params['e'][j]:.3g}" if r.kind == "curve" else
                     f"e = {r.params['e'][j]:.3g}, e_t = {r.params['e_t'][j]:.3g}")
            if r.kind == "curve":
                span = f"for e in {_runs(g, r.params['e'])}"
            else:
                span = (f"at {int(g.sum())}/{g.size} grid points, e in "
                        f"[{r.params['e'][g].min():.3g}, {r.params['e'][g].max():.3g}], e_t in "
                        f"[{r.params['e_t'][g].min():.3g}, {r.params['e_t'][g].max():.3g}]")
            en = f"YES {span}; max dE = +{r.dE[j]:.4g} at {where}"
        lines.append(f"  {name:<28} {pn:<20} {pt:<22} {ref:<22} {en}")
        rng = ", ".join(f"{k} in [{a:g}, {b:g}]" for k, (a, b) in r.ranges.items())
        extra = f"    ({r.kind}: {rng}"
        if r.n_failed:
            extra += f"; no solution at {r.n_failed} samples"
        lines.append(extra + ")")
    return "\n".join(lines)


def impulse_space_report(v, W, mu, n=200, plot=None):
    """Build the ImpulseSpace of one contact, write its plot to ``plot`` (a path) if given,
    and return the text the CLI command ``rbimpact impulse-space`` prints."""
    s = impulse_space(v, W, mu, n=n)
    text = s.summary()
    if plot is not None:
        s.plot(plot)
        text += f"\n\nplot written to {plot}"
    return text


# ---------------------------------------------------------------------------------------------
# plot

def _plot(s, path, ax=None, show_grid_points=False):
    if ax is None:
        # a pyplot-free Figure on the Agg canvas: no GUI backend, nothing left open
        from matplotlib.figure import Figure
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        fig = Figure(figsize=(10.0, 6.5), dpi=110)
        FigureCanvasAgg(fig)
        ax = fig.add_subplot(1, 1, 1)
    else:
        fig = ax.figure

    # x = P_T (horizontal), y = P_N (vertical)
    el = np.vstack([s.ellipse, s.ellipse[:1]])
    ax.fill(el[:, 1], el[:, 0], color="0.93", zorder=0, label="_nolegend_")
    ax.plot(el[:, 1], el[:, 0], color="black", lw=1.4, zorder=2,
            label="dE = 0 (energy ellipse; inside: energy lost)")
    ax.plot(s.cone[:, 1], s.cone[:, 0], color="0.35", ls="--", lw=1.1, zorder=1,
            label=f"friction cone |P_T| = {s.mu:g} P_N")
    gains = []
    for r in s.reach.values():
        colour = _COLOURS[r.law]
        if r.kind == "curve":
            ls = _ROUTH_STYLE[r.fixed["restitution"]] if r.law == "routh" else "-"
            ax.plot(r.P[:, 1], r.P[:, 0], color=colour, ls=ls, lw=2.0, zorder=4,
                    label=f"{r.label}, e in [{r.ranges['e'][0]:g}, {r.ranges['e'][1]:g}]")
        else:
            rng = ", ".join(f"{k} in [{a:g}, {b:g}]" for k, (a, b) in r.ranges.items())
            ax.fill(r.outline[:, 1], r.outline[:, 0], color=colour, alpha=0.13, lw=0,
                    zorder=1, label="_nolegend_")
            if show_grid_points:
                ax.scatter(r.P[:, 1], r.P[:, 0], s=4, color=colour, alpha=0.5, lw=0,
                           zorder=3, label="_nolegend_")
            ax.plot(r.outline[:, 1], r.outline[:, 0], color=colour, lw=1.6, zorder=3,
                    label=f"{r.label} region, {rng}")
        gains.append(r.P[r.energy_gain])
    gains = np.concatenate(gains) if gains else np.zeros((0, 2))
    if gains.shape[0]:
        ax.scatter(gains[:, 1], gains[:, 0], marker="x", s=14, lw=0.8, color="red", zorder=5,
                   label="energy created (dE > 0)")
    ax.plot([s.P_I[1]], [s.P_I[0]], "o", ms=7, mfc="white", mec="black", mew=1.5, zorder=6,
            label="P_I (plastic, frictionless)")
    ax.plot([s.P_II[1]], [s.P_II[0]], "s", ms=7, mfc="black", mec="black", zorder=6,
            label="P_II (plastic, sticking; min dE)")
    ax.plot([2 * s.P_II[1]], [2 * s.P_II[0]], "s", ms=6, mfc="white", mec="black", mew=1.2,
            zorder=6, label="2 P_II (elastic, sticking; dE = 0)")
    for P, txt in ((s.P_I, "P_I"), (s.P_II, "P_II"), (2 * s.P_II, "2 P_II")):
        ax.annotate(txt, (P[1], P[0]), xytext=(7, -13), textcoords="offset points", fontsize=9)
    (nlo, nhi), (tlo, thi) = s.extent
    ax.set_xlim(tlo, thi)
    ax.set_ylim(nlo, nhi)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("tangential impulse P_T [N s]" + (" (along initial slip)" if s.dim == 3 else ""))
    ax.set_ylabel("normal impulse P_N [N s]")
    ax.set_title(f"Impulse space: v = {_fmt(s.v)} m/s, W = {_fmt_W(s.W)} 1/kg, mu = {s.mu:g}",
                 fontsize=10)
    ax.grid(True, lw=0.3, alpha=0.5)
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8.5, frameon=False)
    if path is not None:
        fig.savefig(path, bbox_inches="tight")
    return fig
