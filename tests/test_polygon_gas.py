"""Scenario polygon_gas (issue 16): a gas of random convex polygons (and a mix of polygons,
disks and capsules) in a box of four walls, run by the exact 2D stepper. Elastic and
frictionless: kinetic energy conserved to round-off over hundreds of impacts, momentum
changed only by the wall impulses, no two bodies (and no body and wall) closer than
``-gap_tol`` at any recorded time, and every body-body impact at a touching pair, all
checked with a brute-force distance on the bodies' outlines computed here (independent of
kernels/pair2d*). No timing."""
import math

import numpy as np
import pytest

from rbimpact import scenarios

ENERGY_RTOL = 1e-12     # kinetic energy, relative to itself (round-off of ~1000 impacts)
MOMENTUM_RTOL = 1e-12   # momentum balance, relative to the sum of |wall impulses|
GAP_TOL = 1e-9          # m: the stepper's documented gap_tol (Simulation.TOLERANCES)
TOUCH_TOL = 1e-9        # m: |gap| of the pair of a body-body impact at its time


def _cores(sc, state, k):
    """World core points of every body at sample row k (a disk: its centre; a capsule: its
    segment's ends; a polygon: its corners, counter-clockwise) and their radii."""
    out = []
    for i, b in enumerate(sc.scene.bodies):
        kind, rad, _, _, v = b.shape._kernel()
        c, s = math.cos(state["angle"][k, i]), math.sin(state["angle"][k, i])
        w = v @ np.array([[c, s], [-s, c]]) + [state["x"][k, i], state["y"][k, i]]
        out.append((w, rad))
    return out


def _seg_dist(P, A, B):
    """Smallest distance of the points P (k, 2) from the segments A[j] B[j] (e, 2)."""
    ab = B - A
    L2 = np.sum(ab * ab, axis=1)
    ap = P[:, None, :] - A[None, :, :]
    u = np.clip(np.sum(ap * ab, axis=2) / np.where(L2 > 0.0, L2, 1.0), 0.0, 1.0)
    d = ap - u[:, :, None] * ab
    return float(np.sqrt(np.min(np.sum(d * d, axis=2))))


def _ends(P):
    """The segments of a core: (starts, ends)."""
    if len(P) <= 2:
        return P[:1], P[-1:]
    return P, np.roll(P, -1, axis=0)


def _edges(P):
    A, B = _ends(P)
    return list(zip(A, B))


def _sat(P, Q):
    """Largest separation of polygons P and Q along the outward normals of their edges:
    minus the penetration depth when they overlap (exact for convex polygons)."""
    best = -np.inf
    for A, B in ((P, Q), (Q, P)):
        for a, b in _edges(A):
            n = np.array([b[1] - a[1], a[0] - b[0]])
            n /= np.hypot(*n)
            best = max(best, float(np.min(B @ n) - a @ n))
    return best


def _cross(a, b, c, d):
    """Segments ab and cd cross (properly)."""
    def side(p, q, r):
        return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])
    return (side(a, b, c) * side(a, b, d) < 0.0) and (side(c, d, a) * side(c, d, b) < 0.0)


def _inside(p, P):
    """Point p strictly inside the counter-clockwise polygon P."""
    return all((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]) > 0.0
               for a, b in _edges(P))


def gap(A, B):
    """Signed gap (m) of two bodies given as (core points, radius): the distance of their
    outlines, or minus the penetration depth of two overlapping polygons (other shapes
    whose cores intersect: -inf)."""
    (P, rp), (Q, rq) = A, B
    if len(P) >= 3 and len(Q) >= 3:
        s = _sat(P, Q)
        if s < 0.0:
            return s
    else:
        for X, Y in ((P, Q), (Q, P)):
            if len(Y) >= 3 and any(_inside(x, Y) for x in X):
                return -np.inf
        if any(_cross(a, b, c, d) for a, b in _edges(P) for c, d in _edges(Q)):
            return -np.inf
    d = min(_seg_dist(P, *_ends(Q)), _seg_dist(Q, *_ends(P)))
    return d - rp - rq


def _world_impulse(ev):
    n = ev["normal"]
    t = np.stack([n[:, 1], -n[:, 0]], axis=1)
    return ev["P"][:, :1] * n + ev["P"][:, 1:] * t


def _check_elastic_gas(sc, min_impacts, min_pairs):
    res = sc.simulate()
    assert res.status == "done"
    ev = res.events
    assert np.all(ev["kind"] == "impact")
    pair = ev["b"] >= 0
    assert len(ev) >= min_impacts and pair.sum() >= min_pairs
    # energy: every impact's dE and the state's energy at every event and at the end
    times = np.concatenate([[0.0], ev["t"], [res.t_end]])
    E = res.energy(times)
    assert np.all(np.abs(E / E[0] - 1.0) <= ENERGY_RTOL)
    assert np.all(np.abs(ev["dE"]) <= ENERGY_RTOL * E[0])
    # momentum changes only by the wall impulses
    m = res.masses
    s = res.sample(np.array([0.0, res.t_end]))
    p = np.stack([(m * s["vx"]).sum(axis=1), (m * s["vy"]).sum(axis=1)], axis=1)
    Pw = _world_impulse(ev[~pair])
    assert np.all(np.abs(p[1] - p[0] - Pw.sum(axis=0)) <= MOMENTUM_RTOL * np.abs(Pw).sum())
    # across a body-body impact the total momentum does not change
    Pp = _world_impulse(ev[pair])
    tp = ev["t"][pair]
    eps = 1e-9 * np.maximum(tp, 1.0)
    lo = res.sample(tp - eps)
    hi = res.sample(tp)     # the state just after the event
    for k in range(len(tp)):
        if np.any((ev["t"] > tp[k] - eps[k]) & (ev["t"] < tp[k]) | (ev["t"] == tp[k]) & ~pair):
            continue        # another event in between or at that instant (a wall)
        dp = [(m * (hi[c][k] - lo[c][k])).sum() for c in ("vx", "vy")]
        assert np.all(np.abs(dp) <= MOMENTUM_RTOL * np.abs(Pp[k]).sum() * 10)
    # gaps: every pair and every wall at every event time (and between events), brute force
    L = sc.scene.planes[1].point[0]
    extra = np.linspace(0.0, res.t_end, 97)
    check_t = np.concatenate([ev["t"], extra])
    st = res.sample(check_t)
    nb = len(sc.scene.bodies)
    reach = np.array([b.shape.bounding_radius for b in sc.scene.bodies])
    near = 0
    for k in range(len(check_t)):
        bodies = _cores(sc, st, k)
        xy = np.stack([st["x"][k], st["y"][k]], axis=1)
        for i in range(nb):
            P, r = bodies[i]
            wall = min(P[:, 0].min(), P[:, 1].min(), L - P[:, 0].max(), L - P[:, 1].max()) - r
            assert wall >= -GAP_TOL, (check_t[k], i, wall)
            for j in range(i):
                if np.hypot(*(xy[i] - xy[j])) > reach[i] + reach[j]:
                    continue    # circumcircles apart: the gap is positive
                near += 1
                g = gap(bodies[i], bodies[j])
                assert g >= -GAP_TOL, (check_t[k], i, j, g)
    assert near >= min_pairs    # the brute force did check touching pairs
    # every body-body impact happens at a touching pair
    for k in np.nonzero(pair)[0]:
        bodies = _cores(sc, st, k)
        g = gap(bodies[ev["a"][k]], bodies[ev["b"][k]])
        assert abs(g) <= TOUCH_TOL, (ev["t"][k], ev["a"][k], ev["b"][k], g)
    return res


def test_elastic_polygon_gas_conserves_energy_momentum_and_never_overlaps():
    sc = scenarios.get("polygon_gas", n=10, crossings=20.0, seed=1)
    _check_elastic_gas(sc, min_impacts=300, min_pairs=60)


def test_elastic_mixed_gas_polygons_disks_capsules():
    sc = scenarios.get("polygon_gas", n=9, shapes="mixed", crossings=20.0, seed=2)
    _check_elastic_gas(sc, min_impacts=300, min_pairs=60)


def test_brute_force_gap_on_known_configurations():
    """The test's own distance: two unit squares 0.5 m apart, overlapping by 0.25 m, a
    disk beside a square, a capsule across a square's corner."""
    sq = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    assert math.isclose(gap((sq, 0.0), (sq + [1.5, 0.0], 0.0)), 0.5)
    assert math.isclose(gap((sq, 0.0), (sq + [0.75, 0.3], 0.0)), -0.25)
    assert math.isclose(gap((sq, 0.0), (np.array([[3.0, 0.5]]), 1.0)), 1.0)
    assert math.isclose(gap((sq, 0.0), (np.array([[2.0, 2.0], [3.0, 2.0]]), 0.1)),
                        math.sqrt(2.0) - 0.1)
    assert gap((sq, 0.0), (np.array([[0.5, 0.5]]), 0.1)) == -np.inf
    assert gap((sq, 0.0), (np.array([[-1.0, 0.5], [2.0, 0.5]]), 0.1)) == -np.inf
    seg = np.array([[0.0, 0.0], [2.0, 0.0]])
    assert gap((seg, 0.1), (seg + [0.5, -1.0], 0.2)) == pytest.approx(0.7)
    assert gap((seg, 0.1), (np.array([[1.0, -1.0], [1.0, 1.0]]), 0.2)) == -np.inf


def test_polygon_gas_scenario_bad_input():
    with pytest.raises(ValueError, match="packing"):
        scenarios.get("polygon_gas", packing=0.5)
    with pytest.raises(ValueError, match="max_sides"):
        scenarios.get("polygon_gas", max_sides=2)
    with pytest.raises(ValueError, match="shapes"):
        scenarios.get("polygon_gas", shapes="spheres")
    sc = scenarios.get("polygon_gas", n=5, shapes="mixed", seed=4)
    kinds = [type(b.shape).__name__ for b in sc.scene.bodies]
    assert kinds == ["Polygon", "Disk", "Rod", "Polygon", "Disk"]
    assert len(sc.scene.planes) == 4 and sc.scene.gravity == (0.0, -0.0)
