"""Cross-check against pymunk (Chipmunk2D), and error against run time (DESIGN §7, issue 4).

    >>> from rbimpact.crosscheck import crosscheck_report
    >>> text, rows = crosscheck_report("bouncing_ball", dts=(1e-2, 1e-3, 1e-4))
    >>> print(text)

pymunk is imported only inside the functions of this module (``import rbimpact`` and
``import rbimpact.crosscheck`` do not import it); matplotlib only by the plot.

What pymunk does (pymunk 7 / Munk2D, read from ``cpSpaceStep.c`` and ``cpArbiter.c``):
one step of ``dt`` moves every body with its current velocity (``x += v dt``), finds the
overlapping shapes, sets each contact's bounce target ``-e v_N`` from the velocities at
the start of the step, adds gravity (``v += g dt``) and runs ``iterations`` sweeps of
sequential impulses: Newton restitution with Coulomb friction, friction opposing the
*final* slip, i.e. Kane & Levinson's law for a single contact once the sweeps converge.
Combined coefficients are products: ``e = e_a e_b``, ``mu = mu_a mu_b``. Flight is
symplectic Euler (first order in ``dt``) and an impact is seen only at the end of the
step in which the bodies overlap, so trajectories and impact times converge at first
order in ``dt``.

Settings that make the comparison fair (``to_pymunk`` defaults): ``collision_bias = 1``
(the fraction of overlap left after one second: 1 means overlap is never pushed out,
no position correction), ``collision_slop = 0`` (it only enters that correction),
``collision_persistence = 1`` (a contact is forgotten one step after it separates, so
every new impact starts fresh, without warm-started impulses), ``iterations = 100``,
fixed ``dt``, no damping, no sleeping. Moments of inertia are the scene's, not pymunk's.

Multi-body scenes (issue 16: ``rod_strikes_ball``, ``box_on_box``, ``polygon_collide``):
every body becomes a pymunk body with its own shape and every pair of shapes collides, as
in rbimpact's 2D stepper; body-body and body-plane pairs both combine to the law's ``e``
and ``mu`` (every shape carries ``sqrt(e)``, ``sqrt(mu)``), and ``pair_laws`` set the
arbiter's restitution and friction of their pair in ``pre_solve``. The error measure
covers every body: the report's error is the largest centre-of-mass distance over all
bodies and sample times (``compare``'s ``position_error``; ``position_error_per_body``
per body), and impacts are matched pair by pair.

What the error is made of (measured, pymunk 7.3, dt 1e-2 to 1e-5 s; ``box_on_box`` and
``rod_strikes_ball``): in free flight, symplectic Euler puts a body ``g t dt / 2`` below
its parabola (measured to 2 digits before the first impact); each impact is resolved at
the end of the step in which the shapes overlap, up to one step after the exact instant,
with the geometry and velocities of that moment, which adds an error of order ``dt``
whose constant depends on where the exact impact time falls inside a step (a phase that
changes with ``dt``). So the error is first order but ``error / dt`` scatters: 3.9 to 6.5
m/s for ``rod_strikes_ball`` and 5 to 17 m/s for ``box_on_box`` over dt = 1e-2, 5e-3,
2e-3, ..., 1e-5 s, and the local order between two steps a decade apart ranges from
about 0.7 to 1.2 while a fit over three decades gives 0.9 to 1.05. Solver settings do
not change it for these scenes: each impact has a single contact point, so 10, 100 and
1000 sweeps give the same error to 3 digits, and pymunk's default position correction
(``collision_bias = 0.9**60``, ``collision_slop`` 0 or 0.1) changes the error by less
than 3 % (at dt = 1e-2 s) and not at all below, since the overlap at detection is only
about ``v dt``.

Units: m, kg, s, rad throughout; contact-space vectors normal first (DESIGN §3).
"""
import math
import time
from dataclasses import dataclass, field

import numpy as np

__all__ = ["to_pymunk", "run_pymunk", "compare", "crosscheck_report", "PymunkScene",
           "PymunkRun", "IMPACT_DTYPE", "HORIZON_IMPACTS", "THROUGH_PERSISTENT",
           "EXPECTED_DIFFERENCE"]

#: default solver sweeps per step (DESIGN §7 asks for >= 50)
DEFAULT_ITERATIONS = 100
#: vertices of the polygon standing in for an ellipse (pymunk has no ellipse)
ELLIPSE_VERTICES = 256
#: number of distinct impact instants the report's horizon covers, per scenario; the
#: horizon ends half-way to the next impact instant (and always before the first
#: persistent-contact event, i.e. before a Zeno accumulation).
HORIZON_IMPACTS = {"bouncing_ball": 5, "spinning_ball": 4, "falling_rod": 4,
                   "billiards": 12, "rocking_block": 4, "box_on_box": 8,
                   "rod_strikes_ball": 4}
DEFAULT_HORIZON_IMPACTS = 4
#: scenarios compared through their persistent contacts (the compared interval is not cut
#: at the first persistent-contact event): in ``dominoes`` the first domino pivots on the
#: floor from t = 0 and the struck ones lean on each other, integrated exactly by rbimpact
#: (pivot2d, cluster2d) and stepped by pymunk, whose error still falls at first order in
#: dt (the strikes are plastic, so nothing accumulates; measured in session 30)
THROUGH_PERSISTENT = {"dominoes": 4}
#: spacing of the report's sample times (s); a sample between pymunk steps is taken at
#: the nearest step (see ``run_pymunk``) and compared with the reference at that time.
SAMPLE_SPACING = 1e-3
#: printed for laws other than Kane & Levinson
EXPECTED_DIFFERENCE = ("pymunk implements Newton restitution with Coulomb friction (Kane & "
                       "Levinson's law for a single contact), not {law}: differences are "
                       "expected and are shown anyway")

#: one row per impact pymunk resolved (see ``run_pymunk``)
IMPACT_DTYPE = np.dtype([
    ("t", "f8"), ("step", "i8"), ("a", "i8"), ("b", "i8"), ("n_points", "i8"),
    ("point", "f8", (2,)), ("normal", "f8", (2,)), ("v_i", "f8", (2,)), ("v_f", "f8", (2,)),
    ("P", "f8", (2,)), ("W", "f8", (2, 2)), ("pre", "f8", (2, 3)), ("post", "f8", (2, 3)),
    ("mode", "i8"),
])

_KEYS = ("x", "y", "angle", "vx", "vy", "omega")


# --------------------------------------------------------------------------- building

@dataclass
class PymunkScene:
    """The pymunk equivalent of a ``Scene2D`` (built by ``to_pymunk``).

    ``space`` (``pymunk.Space``), ``bodies`` (``pymunk.Body`` per scene body, same order),
    ``shapes`` (the dynamic shapes, same order), ``planes`` (the static segments, in the
    scene's plane order), ``labels`` (shape -> scene index: body ``i``, plane ``-1 - k``),
    ``pair_materials`` ((a, b) -> (e, mu) overriding the product rule in ``pre_solve``
    for pairs that have their own law), ``notes`` (approximations made, as text),
    ``settings`` (the pymunk settings used).
    """

    space: object
    bodies: list
    shapes: list
    planes: list
    labels: dict
    pair_materials: dict
    notes: list
    settings: dict
    masses: np.ndarray
    moments: np.ndarray
    gravity: np.ndarray


def _law_coefficients(law, what="law"):
    """(e, mu) of a law for pymunk, which needs 0 <= e <= 1 and mu >= 0."""
    p = dict(getattr(law, "params_dict", {}))
    if "e" not in p:
        raise ValueError(f"crosscheck: {what} {law!r} has no restitution e")
    e, mu = float(p["e"]), float(p.get("mu", 0.0))
    if not 0.0 <= e <= 1.0:
        raise ValueError(f"crosscheck: pymunk needs 0 <= e <= 1 (Newton restitution); {what} "
                         f"{law!r} has e = {e:g} (perforation cannot be cross-checked)")
    if not mu >= 0.0:
        raise ValueError(f"crosscheck: {what} {law!r} has mu = {mu:g} < 0")
    return e, mu


def _pair_key(scene, key):
    """A ``Simulation``-style pair_laws key -> (a, b) scene labels, a < b, planes < 0."""
    from .scene import Plane
    if isinstance(key, Plane):
        return ("plane", -1 - key.index)
    a, b = key
    if isinstance(a, Plane):
        a, b = b, a
    if isinstance(b, Plane):
        return (int(a), -1 - b.index)
    a, b = int(a), int(b)
    return (min(a, b), max(a, b))


def to_pymunk(scene, law, pair_laws=None, *, iterations=DEFAULT_ITERATIONS,
              collision_bias=1.0, collision_slop=0.0, collision_persistence=1,
              ellipse_vertices=ELLIPSE_VERTICES, rod_radius=0.0, plane_radius=None,
              plane_half_length=None):
    """Build the pymunk Space of a 2D ``scene`` with collision ``law``; returns a
    ``PymunkScene``.

    Shapes: ``Disk`` -> ``Circle``; ``Box``/``Polygon`` -> ``Poly`` (radius 0);
    ``Rod(L, r)`` -> ``Segment`` of length ``L`` (m) with radius ``r`` (a zero-radius rod
    stays a zero-radius segment, which collides correctly with the thick plane segments;
    ``rod_radius`` (m) replaces a zero radius, e.g. for rod-rod contacts); ``Ellipse`` ->
    a ``Poly`` with ``ellipse_vertices`` vertices on the ellipse (an approximation, stated
    in ``notes``); a circular ``Ellipse`` (a == b) -> ``Circle``. Planes -> static
    ``Segment`` of radius ``plane_radius`` (m, default max(1, 10 x the largest body
    size)) whose surface is the plane, extending ``plane_half_length`` (m, default 1000 m
    or 100 x the scene's extent) either side of the plane's point: a thick slab, so that
    a deep overlap still pushes out on the right side.

    Materials: pymunk combines ``e = e_a e_b`` and ``mu = mu_a mu_b``. With one body the
    planes get 1 and the body the law's ``e`` and ``mu`` (exact); with several bodies
    every shape gets ``sqrt(e)`` and ``sqrt(mu)`` (body-body and body-plane pairs both
    multiply back to ``e`` and ``mu``, to round-off). ``pair_laws`` (same keys as
    ``Simulation``) are honoured by overriding the arbiter's restitution and friction in
    ``pre_solve`` (``run_pymunk`` does it). Bodies take the scene's mass and moment of
    inertia exactly. Settings: ``iterations`` (>= 1; DESIGN §7 asks >= 50),
    ``collision_bias`` (1: no position correction), ``collision_slop`` (m),
    ``collision_persistence`` (steps). No damping, no sleeping.
    """
    pymunk = _import_pymunk()
    from .scene import Scene2D
    if not isinstance(scene, Scene2D):
        raise ValueError(f"to_pymunk: scene must be a Scene2D, got {scene!r}")
    if not scene.bodies:
        raise ValueError("to_pymunk: the scene has no body")
    e, mu = _law_coefficients(law)
    if int(iterations) < 1:
        raise ValueError(f"to_pymunk: iterations must be >= 1, got {iterations!r}")
    from .shapes import Box, Disk, Ellipse, Polygon, Rod

    space = pymunk.Space()
    space.gravity = tuple(float(g) for g in scene.gravity)
    space.iterations = int(iterations)
    space.collision_bias = float(collision_bias)
    space.collision_slop = float(collision_slop)
    space.collision_persistence = int(collision_persistence)
    space.damping = 1.0

    several = len(scene.bodies) > 1
    e_body, mu_body = (math.sqrt(e), math.sqrt(mu)) if several else (e, mu)
    e_plane, mu_plane = (math.sqrt(e), math.sqrt(mu)) if several else (1.0, 1.0)

    notes = []
    bodies, shapes, labels = [], [], {}
    size = max(b.shape.bounding_radius for b in scene.bodies)
    extent = max(max(abs(b.position[0]), abs(b.position[1])) for b in scene.bodies)
    extent = max([extent] + [max(abs(p.point[0]), abs(p.point[1])) for p in scene.planes])
    for body in scene.bodies:
        pb = pymunk.Body(float(body.mass), float(body.moment))
        pb.position = tuple(float(x) for x in body.position)
        pb.angle = float(body.angle)
        pb.velocity = tuple(float(x) for x in body.velocity)
        pb.angular_velocity = float(body.angular_velocity)
        sh = body.shape
        if isinstance(sh, Disk):
            ps = pymunk.Circle(pb, sh.radius)
        elif isinstance(sh, (Box, Polygon)):
            ps = pymunk.Poly(pb, [tuple(map(float, v)) for v in sh.vertices], radius=0.0)
        elif isinstance(sh, Rod):
            r = sh.radius if sh.radius > 0.0 else float(rod_radius)
            if sh.radius == 0.0 and r > 0.0:
                notes.append(f"body {body.index}: a zero-radius rod is a pymunk Segment of "
                             f"radius {r:g} m (rod_radius)")
            elif r == 0.0:
                notes.append(f"body {body.index}: the rod (no thickness) is a zero-radius "
                             f"pymunk Segment; it collides with the thick plane segments, "
                             f"circles and polygons, so no tiny radius is needed (two "
                             f"zero-radius rods need rod_radius)")
            ps = pymunk.Segment(pb, (-0.5 * sh.length, 0.0), (0.5 * sh.length, 0.0), r)
        elif isinstance(sh, Ellipse):
            if sh.a == sh.b:
                ps = pymunk.Circle(pb, sh.a)
            else:
                nv = int(ellipse_vertices)
                th = 2.0 * math.pi * np.arange(nv) / nv
                verts = [(sh.a * math.cos(x), sh.b * math.sin(x)) for x in th]
                ps = pymunk.Poly(pb, verts, radius=0.0)
                sag = max(sh.a, sh.b) * (1.0 - math.cos(math.pi / nv))
                edge = max(math.dist(verts[k], verts[k - 1]) for k in range(nv))
                notes.append(f"body {body.index}: the ellipse (a = {sh.a:g} m, b = {sh.b:g} "
                             f"m) is a {nv}-gon in pymunk (vertices on the ellipse, edges up "
                             f"to {sag:.2g} m inside it): a contact lands on a vertex, up to "
                             f"{0.5 * edge:.2g} m from the exact support point, which changes "
                             f"the impact's lever arm; later bounces amplify the difference")
        else:  # pragma: no cover - every Shape subclass is handled above
            raise ValueError(f"to_pymunk: unsupported shape {sh!r}")
        ps.elasticity = e_body
        ps.friction = mu_body
        space.add(pb, ps)
        bodies.append(pb)
        shapes.append(ps)
        labels[ps] = body.index

    R = float(plane_radius) if plane_radius is not None else max(1.0, 10.0 * size)
    L = (float(plane_half_length) if plane_half_length is not None
         else max(1000.0, 100.0 * extent))
    planes = []
    for plane in scene.planes:
        n = np.array(plane.normal)
        t = np.array([n[1], -n[0]])
        c = np.array(plane.point) - R * n
        seg = pymunk.Segment(space.static_body, tuple(c - L * t), tuple(c + L * t), R)
        seg.elasticity = e_plane
        seg.friction = mu_plane
        space.add(seg)
        planes.append(seg)
        labels[seg] = -1 - plane.index
    if scene.planes:
        notes.append(f"planes are static Segments of radius {R:g} m and length {2 * L:g} m "
                     f"whose surface is the plane")

    pair_materials = {}
    if pair_laws:
        plane_wide = {}
        for key, plaw in dict(pair_laws).items():
            k = _pair_key(scene, key)
            coeffs = _law_coefficients(plaw, f"pair_laws[{key!r}]")
            if k[0] == "plane":
                plane_wide[k[1]] = coeffs
            else:
                pair_materials[k] = coeffs
        for p, coeffs in plane_wide.items():   # a plane alone: every body against it
            for i in range(len(scene.bodies)):
                pair_materials.setdefault((i, p), coeffs)
    settings = dict(iterations=space.iterations, collision_bias=space.collision_bias,
                    collision_slop=space.collision_slop,
                    collision_persistence=space.collision_persistence,
                    plane_radius=R, plane_half_length=L,
                    materials=("sqrt(e), sqrt(mu) on every shape" if several
                               else "body e, mu; planes 1, 1"))
    return PymunkScene(space, bodies, shapes, planes, labels, pair_materials, notes,
                       settings, np.array([b.mass for b in scene.bodies]),
                       np.array([b.moment for b in scene.bodies]),
                       np.array(scene.gravity, dtype=float))


# --------------------------------------------------------------------------- running

@dataclass
class PymunkRun:
    """What ``run_pymunk`` observed.

    ``times`` (s): the requested sample times; ``t`` (s): the step times actually
    sampled (``round(time / dt) * dt``); ``states``: dict "x", "y" (m), "angle" (rad),
    "vx", "vy" (m/s), "omega" (rad/s), each ``(len(times), n_bodies)``, like
    ``Result.sample``; ``impacts``: ``IMPACT_DTYPE`` array (see ``run_pymunk``);
    ``run_time`` (s): wall clock of the ``space.step`` calls only (building and
    sampling excluded); ``dt`` (s), ``n_steps``, ``t_end`` (s), ``notes``, ``settings``.
    """

    times: np.ndarray
    t: np.ndarray
    states: dict
    impacts: np.ndarray
    run_time: float
    dt: float
    n_steps: int
    t_end: float
    masses: np.ndarray
    moments: np.ndarray
    gravity: np.ndarray
    notes: list = field(default_factory=list)
    settings: dict = field(default_factory=dict)

    def sample(self, times=None):
        """The sampled states (dict as ``Result.sample``); ``times`` must be None or the
        run's own sample times."""
        if times is not None and not np.array_equal(np.asarray(times, float), self.times):
            raise ValueError("PymunkRun.sample: pymunk states exist only at the run's "
                             "sample times")
        return self.states

    def energy(self, per_body=False):
        """Total mechanical energy (J) at the sampled steps, like ``Result.energy``."""
        return _energy(self.states, self.masses, self.moments, self.gravity, per_body)


def _energy(s, masses, moments, gravity, per_body=False):
    e = (0.5 * masses * (s["vx"] ** 2 + s["vy"] ** 2) + 0.5 * moments * s["omega"] ** 2
         - masses * (gravity[0] * s["x"] + gravity[1] * s["y"]))
    return e if per_body else e.sum(axis=1)


def _cross(r, d):
    return r[0] * d[1] - r[1] * d[0]


def run_pymunk(scene, law, t_end, dt, times=None, *, pair_laws=None, impact_speed=None,
               record_impacts=True, **settings):
    """Run ``scene`` in pymunk with fixed step ``dt`` (s) up to ``t_end`` (s); returns a
    ``PymunkRun``.

    ``times`` (s, default 201 times evenly spaced in [0, t_end]): the state is read after
    step ``n = round(time / dt)``, i.e. a time between two steps is snapped to the nearest
    step (no interpolation); the times actually sampled are ``run.t`` and ``compare``
    evaluates the reference at those times. ``settings`` go to ``to_pymunk``.

    Impacts: pymunk resolves a contact in the step in which the shapes overlap. An impact
    is recorded when, at the start of that step, the normal velocity of the contact point
    approaches faster than ``impact_speed`` (m/s; default ``2 |g| dt``, so that resting
    contact, which gravity pushes in by ``|g| dt`` per step, is not counted). Its time
    is the end of the step (``step * dt``); ``pre`` velocities are read in ``pre_solve``
    (before gravity and impulses of the step), ``P`` from ``arbiter.total_impulse`` in
    ``post_solve`` and ``post`` velocities there too (after all sweeps). Contact space
    follows DESIGN §3: ``a`` the body with the lower index, ``b`` the other body or
    ``-1 - plane``, ``normal`` from B into A, ``v_i``/``v_f`` the velocity of A's contact
    point minus B's (normal first; each body's arm is its own contact point, as in the
    solver), ``P`` the impulse on A, ``W`` the Delassus matrix at those arms, ``pre`` and
    ``post`` rows ``(vx, vy, omega)`` of A and B (zeros for a plane), ``mode`` 1 inside the
    friction cone (stick), 2 on it (slip). With several contact points in one arbiter (a
    face landing flat) the point approaching fastest is reported and ``P`` is the total.
    The impulse includes ``m g dt`` of the step's gravity.
    """
    dt = float(dt)
    t_end = float(t_end)
    if not (math.isfinite(dt) and dt > 0.0):
        raise ValueError(f"run_pymunk: dt must be a positive time step (s), got {dt!r}")
    if not (math.isfinite(t_end) and t_end >= 0.0):
        raise ValueError(f"run_pymunk: t_end must be a finite time >= 0 (s), got {t_end!r}")
    pm = to_pymunk(scene, law, pair_laws, **settings)
    space, bodies = pm.space, pm.bodies
    n_end = int(round(t_end / dt))
    if times is None:
        times = np.linspace(0.0, t_end, 201)
    times = np.atleast_1d(np.asarray(times, dtype=float))
    if times.ndim != 1 or not np.all(np.isfinite(times)) or (times.size and times.min() < 0):
        raise ValueError("run_pymunk: times must be a 1-D array of finite times >= 0 (s)")
    steps = np.rint(times / dt).astype(np.int64)
    if steps.size and steps.max() > n_end:
        raise ValueError(f"run_pymunk: sample times go beyond t_end = {t_end:g} s")
    g = float(np.hypot(*pm.gravity))
    v_tol = (2.0 * g * dt if impact_speed is None else float(impact_speed)) + 1e-12
    masses, moments = pm.masses, pm.moments
    labels, mats = pm.labels, pm.pair_materials

    cur = [0]                 # index of the step in progress (1-based after the step)
    pending = {}
    records = []

    def body_state(i):
        if i < 0:
            return (0.0, 0.0, 0.0), (0.0, 0.0)
        b = bodies[i]
        v, p = b.velocity, b.position
        return (v.x, v.y, b.angular_velocity), (p.x, p.y)

    def contact_velocity(state, arm, d):
        v0, v1, w = state
        return (v0 - w * arm[1]) * d[0] + (v1 + w * arm[0]) * d[1]

    def pre_solve(arb, space_, data):
        sa, sb = arb.shapes
        la, lb = labels[sa], labels[sb]
        if mats:
            key = (min(la, lb), max(la, lb)) if min(la, lb) >= 0 else (max(la, lb),
                                                                       min(la, lb))
            if key in mats:
                arb.restitution, arb.friction = mats[key]
        if not record_impacts:
            return
        nrm = arb.normal                       # from shapes[0] to shapes[1]
        if lb >= 0 and (la < 0 or lb < la):    # A = shapes[1]
            A, B, sgn, swap = lb, la, 1.0, True
        else:
            A, B, sgn, swap = la, lb, -1.0, False
        n = (sgn * nrm.x, sgn * nrm.y)
        t = (n[1], -n[0])
        sA, pA = body_state(A)
        sB, pB = body_state(B)
        best = None
        pts = arb.contact_point_set.points
        for cp in pts:
            qa, qb = (cp.point_b, cp.point_a) if swap else (cp.point_a, cp.point_b)
            rA = (qa.x - pA[0], qa.y - pA[1])
            rB = (qb.x - pB[0], qb.y - pB[1]) if B >= 0 else (0.0, 0.0)
            vn = contact_velocity(sA, rA, n) - (contact_velocity(sB, rB, n) if B >= 0 else 0.0)
            if best is None or vn < best[0]:
                best = (vn, rA, rB, (0.5 * (qa.x + qb.x), 0.5 * (qa.y + qb.y)))
        if best is None or best[0] >= -v_tol:
            return
        pending[(la, lb)] = (cur[0], A, B, swap, n, t, best, sA, sB, len(pts))

    def post_solve(arb, space_, data):
        sa, sb = arb.shapes
        item = pending.pop((labels[sa], labels[sb]), None)
        if item is None or item[0] != cur[0]:      # nothing recorded in this step
            return
        _, A, B, swap, n, t, (vn, rA, rB, point), sA, sB, npts = item
        J = arb.total_impulse                  # impulse on shapes[0]
        s = -1.0 if swap else 1.0              # -> impulse on A
        P = (s * J.x, s * J.y)
        fA, _ = body_state(A)
        fB, _ = body_state(B)
        dirs = (n, t)

        def rel(state_a, state_b, d):
            out = contact_velocity(state_a, rA, d)
            if B >= 0:
                out -= contact_velocity(state_b, rB, d)
            return out

        W = np.zeros((2, 2))
        for i in range(2):
            for j in range(2):
                w = (dirs[i][0] * dirs[j][0] + dirs[i][1] * dirs[j][1]) / masses[A] \
                    + _cross(rA, dirs[i]) * _cross(rA, dirs[j]) / moments[A]
                if B >= 0:
                    w += (dirs[i][0] * dirs[j][0] + dirs[i][1] * dirs[j][1]) / masses[B] \
                        + _cross(rB, dirs[i]) * _cross(rB, dirs[j]) / moments[B]
                W[i, j] = w
        PN = P[0] * n[0] + P[1] * n[1]
        PT = P[0] * t[0] + P[1] * t[1]
        mu_c = arb.friction
        mode = 1 if abs(PT) < (1.0 - 1e-6) * mu_c * PN else 2
        records.append((cur[0] * dt, cur[0], A, B, npts, point, n,
                        (rel(sA, sB, n), rel(sA, sB, t)), (rel(fA, fB, n), rel(fA, fB, t)),
                        (PN, PT), W, (sA, sB), (fA, fB), mode))

    space.on_collision(pre_solve=pre_solve, post_solve=post_solve)

    nb = len(bodies)
    out = {k: np.empty((times.size, nb)) for k in _KEYS}
    order = np.argsort(steps, kind="stable")
    step_fn = space.step
    clock = time.perf_counter
    run_time = 0.0
    done = 0

    def advance(to):
        nonlocal done, run_time
        t0 = clock()
        for k in range(done + 1, to + 1):
            cur[0] = k
            step_fn(dt)
        run_time += clock() - t0
        done = max(done, to)

    for k in order:
        advance(int(steps[k]))
        for i, b in enumerate(bodies):
            p, v = b.position, b.velocity
            out["x"][k, i] = p.x
            out["y"][k, i] = p.y
            out["angle"][k, i] = b.angle
            out["vx"][k, i] = v.x
            out["vy"][k, i] = v.y
            out["omega"][k, i] = b.angular_velocity
    advance(n_end)
    impacts = np.array(records, dtype=IMPACT_DTYPE) if records else np.zeros(0, IMPACT_DTYPE)
    return PymunkRun(times, steps * dt, out, impacts, run_time, dt, n_end, n_end * dt,
                     masses, moments, pm.gravity, list(pm.notes), dict(pm.settings))


# --------------------------------------------------------------------------- comparing

def _match(ref_t, pm_t, window):
    """Match two sorted time lists in order: pairs (i, j) with |ref_t[i] - pm_t[j]| <=
    window, advancing past the earlier of two unmatched times."""
    pairs, i, j = [], 0, 0
    while i < len(ref_t) and j < len(pm_t):
        d = pm_t[j] - ref_t[i]
        if abs(d) <= window:
            pairs.append((i, j))
            i += 1
            j += 1
        elif d < 0:
            j += 1
        else:
            i += 1
    return pairs


def compare(result, pymunk_run, *, window=None):
    """Error measures of a ``PymunkRun`` against a reference ``result`` (an
    ``rbimpact.Result``, or any object with ``sample(times)``, ``energy(times)``,
    ``events`` and ``t_end``); returns a dict.

    Trajectories (at the pymunk sample times ``run.t`` not after ``result.t_end``):
    ``position_error`` (m, max over times and bodies of the centre-of-mass distance),
    ``position_error_per_body`` (m), ``angle_error`` (rad), ``velocity_error`` (m/s),
    ``omega_error`` (rad/s), ``energy_error`` (J, max |E_pymunk - E_ref|),
    ``energy_difference_end`` (J, at the last sample), ``n_samples``.

    Impacts: the reference impacts (events of kind "impact") and pymunk's are matched per
    pair of bodies (or body and plane), in time order, when they lie within ``window``
    (s) of each other; by default half the shortest interval between two reference
    impacts of that pair (at least ``2 dt``; no limit for a pair the reference sees only
    once), i.e. a pymunk impact is matched to the reference impact of the same pair that
    it is closest to, in order. ``impacts``: list of dicts (``a``, ``b``, ``t_ref``,
    ``t_pymunk``, ``dt_impact`` (s), ``v_f_ref``, ``v_f_pymunk`` (m/s, contact space),
    ``dv_f`` (m/s, norm of the difference), ``P_ref``, ``P_pymunk`` (N s));
    ``impact_time_error`` (s) and ``post_velocity_error`` (m/s): the largest over matched
    impacts; ``n_matched``; ``n_missed`` (reference impacts up to the run's end less
    ``min(window, 10 dt)`` with no pymunk match); ``n_extra`` (pymunk impacts, up to the
    reference's end, with no match).
    """
    run = pymunk_run
    t = np.asarray(run.t, dtype=float)
    slack = 1e-9 * max(1.0, abs(float(result.t_end)))
    keep = t <= float(result.t_end) + slack
    tk = np.minimum(t[keep], float(result.t_end))
    ref = result.sample(tk)
    pm = {k: np.asarray(v)[keep] for k, v in run.states.items()}
    out = {"n_samples": int(keep.sum())}
    if keep.any():
        dpos = np.hypot(pm["x"] - ref["x"], pm["y"] - ref["y"])
        out["position_error_per_body"] = dpos.max(axis=0)
        out["position_error"] = float(dpos.max())
        out["angle_error"] = float(np.abs(pm["angle"] - ref["angle"]).max())
        out["velocity_error"] = float(np.hypot(pm["vx"] - ref["vx"], pm["vy"] - ref["vy"]).max())
        out["omega_error"] = float(np.abs(pm["omega"] - ref["omega"]).max())
        e_ref = np.asarray(result.energy(tk), dtype=float)
        e_pm = _energy(pm, run.masses, run.moments, run.gravity)
        out["energy_error"] = float(np.abs(e_pm - e_ref).max())
        out["energy_difference_end"] = float(e_pm[-1] - e_ref[-1])
    else:
        for k in ("position_error", "angle_error", "velocity_error", "omega_error",
                  "energy_error", "energy_difference_end"):
            out[k] = math.nan
        out["position_error_per_body"] = np.full(len(run.masses), math.nan)

    ev = result.events
    ev = ev[(ev["kind"] == "impact") & (ev["t"] <= run.t_end + slack)]
    imp = run.impacts
    imp = imp[imp["t"] <= float(result.t_end) + slack]
    matches, n_missed = [], 0
    pairs = sorted(set(zip(ev["a"].tolist(), ev["b"].tolist()))
                   | set(zip(imp["a"].tolist(), imp["b"].tolist())))
    matched_pm = 0
    for a, b in pairs:
        r = ev[(ev["a"] == a) & (ev["b"] == b)]
        p = imp[(imp["a"] == a) & (imp["b"] == b)]
        if window is not None:
            win = float(window)
        else:
            gaps = np.diff(r["t"])
            gaps = gaps[gaps > 0]
            win = max(0.5 * float(gaps.min()), 2.0 * run.dt) if gaps.size else math.inf
        mp = _match(r["t"], p["t"], win)
        matched_pm += len(mp)
        hit = {i for i, _ in mp}
        late = run.t_end - min(win, 10.0 * run.dt)   # pymunk may see these after its end
        n_missed += sum(1 for i in range(len(r)) if i not in hit and r["t"][i] <= late)
        for i, j in mp:
            matches.append(dict(
                a=int(a), b=int(b), t_ref=float(r["t"][i]), t_pymunk=float(p["t"][j]),
                dt_impact=float(p["t"][j] - r["t"][i]),
                v_f_ref=np.array(r["v_f"][i]), v_f_pymunk=np.array(p["v_f"][j]),
                dv_f=float(np.hypot(*(p["v_f"][j] - r["v_f"][i]))),
                P_ref=np.array(r["P"][i]), P_pymunk=np.array(p["P"][j])))
    matches.sort(key=lambda m: (m["t_ref"], m["a"], m["b"]))
    out["impacts"] = matches
    out["n_matched"] = len(matches)
    out["n_missed"] = int(n_missed)
    out["n_extra"] = int(len(imp) - matched_pm)
    out["impact_time_error"] = (max(abs(m["dt_impact"]) for m in matches) if matches
                                else math.nan)
    out["post_velocity_error"] = (max(m["dv_f"] for m in matches) if matches else math.nan)
    return out


# --------------------------------------------------------------------------- references

class _BounceReference:
    """The exact bouncing ball (scenario reference: impact times t_k and speeds), as an
    object with ``sample``, ``energy``, ``events``, ``t_end``: a disk of radius ``r``
    dropped from rest, its lowest point at ``h``, bouncing with restitution ``e`` on a
    floor at y = 0, horizontal velocity ``vx`` kept (exact when ``vx == 0`` or
    ``mu == 0``: no impulse along the floor, no spin)."""

    def __init__(self, ref, x0, radius, vx, mass, moment, t_end):
        self.ref = ref
        self.x0, self.r, self.vx = float(x0), float(radius), float(vx)
        self.masses = np.array([float(mass)])
        self.moments = np.array([float(moment)])
        self.gravity = np.array([0.0, -ref.g])
        self.t_end = float(t_end)
        n = 8
        while True:
            tk = ref.impact_times(n)
            if tk[-1] > self.t_end or n > 1_000_000:
                break
            n *= 2
        self.t_imp = tk[tk <= self.t_end]
        m = len(self.t_imp)
        v_in = ref.impact_speeds(m)
        ev = np.zeros(m, dtype=[("t", "f8"), ("kind", "U8"), ("a", "i8"), ("b", "i8"),
                                ("v_i", "f8", (2,)), ("v_f", "f8", (2,)), ("P", "f8", (2,))])
        ev["t"] = self.t_imp
        ev["kind"] = "impact"
        ev["a"], ev["b"] = 0, -1
        ev["v_i"][:, 0] = -v_in
        ev["v_i"][:, 1] = self.vx
        ev["v_f"][:, 0] = ref.e * v_in
        ev["v_f"][:, 1] = self.vx
        ev["P"][:, 0] = mass * (1.0 + ref.e) * v_in
        self.events = ev

    def sample(self, times):
        t = np.atleast_1d(np.asarray(times, dtype=float))
        g = self.ref.g
        k = np.searchsorted(self.t_imp, t, side="right")      # impacts at or before t
        tk = np.where(k > 0, self.t_imp[np.maximum(k - 1, 0)], 0.0)
        v0 = np.where(k > 0, self.ref.v0 * self.ref.e ** k, 0.0)
        y0 = np.where(k > 0, self.r, self.ref.h + self.r)
        s = t - tk
        y = y0 + v0 * s - 0.5 * g * s * s
        vy = v0 - g * s
        col = lambda a: np.asarray(a, dtype=float).reshape(-1, 1)  # noqa: E731
        return {"x": col(self.x0 + self.vx * t), "y": col(y), "angle": col(np.zeros_like(t)),
                "vx": col(np.full_like(t, self.vx)), "vy": col(vy),
                "omega": col(np.zeros_like(t))}

    def energy(self, times):
        return _energy(self.sample(times), self.masses, self.moments, self.gravity)


def _analytic_reference(sc, t_end):
    """The scenario's exact trajectory where one exists (bouncing_ball), else None."""
    ref = sc.reference
    if sc.name != "bouncing_ball" or ref is None or not hasattr(ref, "impact_times"):
        return None
    p = sc.params
    if p.get("vx", 0.0) != 0.0 and p.get("mu", 0.0) != 0.0:
        return None
    if sc.law.name == "brach" and (p.get("e_t", 0.0) != 0.0 or p.get("e", 0.0) < 0.0):
        return None
    body = sc.scene.bodies[0]
    return _BounceReference(ref, body.position[0], body.shape.radius, body.velocity[0],
                            body.mass, body.moment, t_end)


# --------------------------------------------------------------------------- the report

def _median(xs):
    return float(np.median(np.asarray(xs, dtype=float)))


def _horizon(events, t_stop, n_instants):
    """End of the compared interval (s): half-way between the ``n_instants``-th distinct
    impact instant and the next impact instant (or ``t_stop``, the first persistent-
    contact event or the end of the run), and the number of instants covered."""
    imp = np.unique(np.round(events["t"][(events["kind"] == "impact")
                                         & (events["t"] < t_stop)], 12))
    if imp.size == 0:
        return float(t_stop), 0
    n = min(n_instants, imp.size)
    nxt = imp[n] if n < imp.size else t_stop
    return float(0.5 * (imp[n - 1] + nxt)), n


def _order(dts, errs):
    """Least-squares slope of log(error) against log(dt) (nan with fewer than 2 points)."""
    x = np.log(np.asarray(dts, dtype=float))
    y = np.asarray(errs, dtype=float)
    ok = np.isfinite(y) & (y > 0)
    if ok.sum() < 2:
        return math.nan
    return float(np.polyfit(x[ok], np.log(y[ok]), 1)[0])


def _local_orders(dts, errs):
    """(dt_a, dt_b, order) for consecutive dts with positive finite errors."""
    out = []
    for (a, ea), (b, eb) in zip(zip(dts, errs), list(zip(dts, errs))[1:]):
        if ea > 0 and eb > 0 and math.isfinite(ea) and math.isfinite(eb) and a != b:
            out.append((a, b, math.log(ea / eb) / math.log(a / b)))
    return out


def _fmt(x, spec=".3g"):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "-"
    return format(x, spec)


def _dt_label(dt):
    m, e = f"{dt:.0e}".split("e")
    return f"{m}e{int(e)}"


def crosscheck_report(name, dts=(1e-2, 1e-3, 1e-4, 1e-5), repeat=3, out=None, plot=None,
                      law=None, settings=()):
    """Work-precision cross-check of scenario ``name``: pymunk over the ``dts`` ladder (s)
    against the exact reference, and rbimpact's event-driven run. Returns ``(text,
    rows)``: the printed table and one dict per row.

    ``law``: the law's name (default ``kane_levinson``, the law pymunk implements, when
    the scenario supports it, else the scenario's default); ``settings``: scenario
    ``key=value`` strings (as ``rbimpact run --set``). Reference: the scenario's analytic
    trajectory where it has one (bouncing_ball with vx = 0 or mu = 0), else rbimpact's
    event-driven run. The compared interval ends before the first persistent contact
    (Zeno accumulation) and covers the first ``HORIZON_IMPACTS[name]`` impact instants
    (4 if not listed); scenarios in ``THROUGH_PERSISTENT`` are compared through their
    persistent contacts over that many impact instants (a scene in persistent contact
    from t = 0 that is not listed there: ``ValueError``). Error: the largest distance (m) between the engine's and the
    reference's centre of mass of a body, over every body of the scene and over sample
    times every ``SAMPLE_SPACING`` s (pymunk: taken at the nearest step); with several
    bodies the text also gives each body's own largest distance (rows:
    ``error_per_body_m``). ``error/dt`` (m/s) is printed per ``dt``: about constant when
    the error is first order; the local order between consecutive ``dt`` is printed
    with the fitted one. Run times: median of ``repeat`` runs, pymunk's
    ``space.step`` calls only, rbimpact's ``Simulation.run`` warm (after a first,
    compiling run); building and sampling are excluded from both. ``out``: write the rows
    to this CSV file; ``plot``: write a log-log plot of error against run time (PNG).
    """
    from . import scenarios
    from .errors import NoSolutionError, SimulationError
    dts = sorted((float(x) for x in dts), reverse=True)
    if not dts or any(not (math.isfinite(x) and x > 0) for x in dts):
        raise ValueError(f"crosscheck: dts must be positive time steps (s), got {dts!r}")
    repeat = int(repeat)
    if repeat < 1:
        raise ValueError(f"crosscheck: repeat must be >= 1, got {repeat!r}")
    spec = scenarios.spec(name)
    params = scenarios.parse_settings(name, list(settings or ()))
    if law is not None:
        params["law"] = law
    elif "law" not in params:
        params["law"] = "kane_levinson" if "kane_levinson" in spec.laws else spec.default_law
    sc = scenarios.get(name, **params)
    _law_coefficients(sc.law)

    # the event-driven run over the scenario's whole time: where the compared interval ends
    sim = sc.simulation()
    stop_note = ""
    try:
        full = sim.run(sc.t_end, max_events=sc.max_events)
    except (SimulationError, NoSolutionError) as exc:
        full = getattr(exc, "result", None)
        if full is None:
            raise
        stop_note = (f"the event-driven run stops at t = {full.t_end:.6g} s "
                     f"({type(exc).__name__}: {exc}); the comparison ends before")
    ev = full.events
    through = name in THROUGH_PERSISTENT
    persistent = ev["t"][:0] if through else ev["t"][ev["kind"] != "impact"]
    t_stop = float(persistent.min()) if persistent.size else float(full.t_end)
    horizon, n_inst = _horizon(ev, t_stop, THROUGH_PERSISTENT[name] if through else
                               HORIZON_IMPACTS.get(name, DEFAULT_HORIZON_IMPACTS))
    if stop_note and n_inst == 0:
        raise ValueError(f"crosscheck {name}: the event-driven run with law {sc.law.name} "
                         f"fails before its first impact is resolved, so there is nothing "
                         f"to compare: {stop_note}")
    if not horizon > 0.0:
        raise ValueError(f"crosscheck {name}: the scene is in persistent contact from t = 0 "
                         f"(its first event, '{ev['kind'][0]}', is at {t_stop:.6g} s), and "
                         f"the comparison ends at the first persistent contact, so there is "
                         f"nothing to compare; scenes compared through persistent contact: "
                         f"{', '.join(sorted(THROUGH_PERSISTENT))}")
    dt_max = max(dts)
    spacing = min(SAMPLE_SPACING, horizon / 50.0)
    times = np.arange(0.0, horizon + 0.5 * spacing, spacing)
    times = times[times <= horizon]

    # rbimpact: warm runs to the horizon (plus a step, so every snapped sample is covered)
    t_rb = horizon + dt_max
    if persistent.size or stop_note:       # stay before the contact switch or the failure
        t_rb = min(t_rb, 0.5 * (horizon + t_stop))
    sim.run(t_rb, max_events=sc.max_events)                  # compiled already; warm-up
    rb_times, rb = [], None
    for _ in range(repeat):
        s2 = sc.simulation()
        t0 = time.perf_counter()
        rb = s2.run(t_rb, max_events=sc.max_events)
        rb_times.append(time.perf_counter() - t0)
    analytic = _analytic_reference(sc, t_rb)
    reference = analytic if analytic is not None else rb

    rows = []
    law_name = sc.law.name
    law_text = ", ".join(f"{k}={v:g}" if not isinstance(v, str) else f"{k}={v}"
                         for k, v in sc.law.params_dict.items() if k != "tol")
    notes = []
    orders_dt, orders_err = [], []
    for dt in dts:
        run = None
        times_pm = []
        for _ in range(repeat):
            run = run_pymunk(sc.scene, sc.law, horizon + dt_max, dt, times,
                             pair_laws=sc.pair_laws)
            times_pm.append(run.run_time)
        cmp_ = compare(reference, run)
        notes = run.notes
        rows.append(dict(scenario=name, law=law_name, engine="pymunk",
                         setting=f"dt={_dt_label(dt)}", dt_s=dt, run_time_s=_median(times_pm),
                         error_m=cmp_["position_error"],
                         error_per_body_m=tuple(float(x) for x in
                                                cmp_["position_error_per_body"]),
                         angle_error_rad=cmp_["angle_error"],
                         impact_time_error_s=cmp_["impact_time_error"],
                         post_velocity_error_m_s=cmp_["post_velocity_error"],
                         impacts_matched=cmp_["n_matched"], impacts_missed=cmp_["n_missed"],
                         impacts_extra=cmp_["n_extra"],
                         energy_diff_end_J=cmp_["energy_difference_end"], reference=False))
        orders_dt.append(dt)
        orders_err.append(cmp_["position_error"])
    if analytic is not None:
        # rbimpact's own error against the analytic reference, at the sample times
        ex = PymunkRun(times, times, rb.sample(times), np.zeros(0, IMPACT_DTYPE), 0.0, 0.0, 0,
                       horizon, rb.masses, rb.moments, rb.gravity)
        cmp_rb = compare(analytic, ex)
        ev_rb = rb.events[rb.events["kind"] == "impact"]
        ev_ex = analytic.events
        m = min(len(ev_rb), len(ev_ex))
        t_err = float(np.max(np.abs(ev_rb["t"][:m] - ev_ex["t"][:m]))) if m else math.nan
        v_err = (float(np.max(np.hypot(*(ev_rb["v_f"][:m] - ev_ex["v_f"][:m]).T)))
                 if m else math.nan)
        rb_row = dict(error_m=cmp_rb["position_error"],
                      error_per_body_m=tuple(float(x) for x in
                                             cmp_rb["position_error_per_body"]),
                      angle_error_rad=cmp_rb["angle_error"],
                      impact_time_error_s=t_err, post_velocity_error_m_s=v_err,
                      impacts_matched=m, impacts_missed=0, impacts_extra=0,
                      energy_diff_end_J=cmp_rb["energy_difference_end"], reference=False)
    else:
        rb_row = dict(error_m=0.0, error_per_body_m=(0.0,) * len(sc.scene.bodies),
                      angle_error_rad=0.0, impact_time_error_s=0.0,
                      post_velocity_error_m_s=0.0,
                      impacts_matched=int(np.count_nonzero(
                          (rb.events["kind"] == "impact") & (rb.events["t"] <= horizon))),
                      impacts_missed=0, impacts_extra=0, energy_diff_end_J=0.0, reference=True)
    rows.append(dict(scenario=name, law=law_name, engine="rbimpact", setting="event-driven",
                     dt_s=math.nan, run_time_s=_median(rb_times), **rb_row))
    order = _order(orders_dt, orders_err)

    # ---- text
    ref_text = ("analytic (the scenario's exact impact times and parabolic flights)"
                if analytic is not None else "rbimpact's event-driven run (exact flight, "
                "impact times root-found to ~1e-12 relative)")
    lines = [f"crosscheck {name}: {spec.summary}",
             f"law: {law_name} ({law_text})"]
    if law_name != "kane_levinson":
        lines.append("note: " + EXPECTED_DIFFERENCE.format(law=law_name))
    lines.append(f"reference: {ref_text}")
    lines.append(f"compared interval: [0, {horizon:.6g}] s, the first {n_inst} impact "
                 f"instant(s)" + (f", before the persistent contact (Zeno) at "
                                  f"{t_stop:.6g} s" if persistent.size else "")
                 + (", through the persistent contacts (pivoting, leaning; integrated by "
                    "rbimpact, stepped by pymunk)" if through else ""))
    if stop_note:
        lines.append(stop_note)
    if hasattr(sc.reference, "t1") and not hasattr(sc.reference, "impact_times"):
        lines.append(f"exact first impact: t1 = {sc.reference.t1:.9f} s (scenario "
                     f"reference)")
    nb = len(sc.scene.bodies)
    lines.append("error: max distance (m) between a body's centre of mass in the engine and "
                 "in the reference, over " + (f"all {nb} bodies and " if nb > 1 else "")
                 + f"{times.size} sample times every {spacing:g} s (pymunk: at the nearest "
                 f"step)")
    lines.append(f"pymunk {_pymunk_version()}: iterations {run.settings['iterations']}, "
                 f"collision_bias {run.settings['collision_bias']:g} (no position "
                 f"correction), collision_slop {run.settings['collision_slop']:g}, "
                 f"collision_persistence {run.settings['collision_persistence']}, materials "
                 f"{run.settings['materials']}")
    for note in notes:
        lines.append(f"pymunk model: {note}")
    lines.append(f"run time: median of {repeat}; pymunk: space.step calls only; rbimpact: "
                 f"Simulation.run, warm")
    header = ("engine", "setting", "run time (s)", "error (m)", "error/dt (m/s)",
              "angle err (rad)", "impact t err (s)", "post v err (m/s)", "impacts",
              "dE end (J)")
    table = []
    for r in rows:
        ref_mark = r["reference"]
        table.append((r["engine"], r["setting"], _fmt(r["run_time_s"]),
                      "0 (reference)" if ref_mark else _fmt(r["error_m"]),
                      _fmt(r["error_m"] / r["dt_s"]) if r["engine"] == "pymunk" else "-",
                      "-" if ref_mark else _fmt(r["angle_error_rad"]),
                      "-" if ref_mark else _fmt(r["impact_time_error_s"]),
                      "-" if ref_mark else _fmt(r["post_velocity_error_m_s"]),
                      f"{r['impacts_matched']}" + (
                          f" (-{r['impacts_missed']} +{r['impacts_extra']})"
                          if r["engine"] == "pymunk" and (r["impacts_missed"]
                                                          or r["impacts_extra"]) else ""),
                      "-" if ref_mark else _fmt(r["energy_diff_end_J"], "+.3g")))
    widths = [max(len(str(x[i])) for x in (header, *table)) for i in range(len(header))]
    fmt = "  ".join("{:<%d}" % w for w in widths)
    lines.append(fmt.format(*header))
    lines.append("  ".join("-" * w for w in widths))
    lines += [fmt.format(*x) for x in table]
    lines.append("impacts: matched with the reference (-missed +extra); impact t err and "
                 "post v err: largest over matched impacts (post-impact contact velocity, "
                 "normal first); dE end: total energy minus the reference's at the end of "
                 "the interval")
    lines.append(f"pymunk observed order of convergence: {_fmt(order, '.2f')} (least-squares "
                 f"slope of log error against log dt)")
    local = _local_orders(orders_dt, orders_err)
    if local:
        lines.append("local order between consecutive dt: " + ", ".join(
            f"{_dt_label(a)}->{_dt_label(b)} {_fmt(p, '.2f')}" for a, b, p in local)
            + " (each impact is seen at the end of the step after it: the constant of the "
            "first-order error depends on where the impact times fall inside a step, so "
            "the local order scatters around the fitted one)")
    if nb > 1:
        role = {int(i): str(k) for k, i in dict(sc.bodies).items()}
        lines.append("error per body (m, max over the sample times): " + "; ".join(
            f"{r['setting']}: " + ", ".join(
                f"{role.get(i, f'body {i}')} {_fmt(x)}"
                for i, x in enumerate(r["error_per_body_m"]))
            for r in rows if r["engine"] == "pymunk"))
    ratios = _ratios(rows)
    lines += ratios
    if out:
        _write_csv(out, rows)
        lines.append(f"table written to {out}")
    if plot:
        _plot(plot, rows, order, name, law_name, analytic is not None)
        lines.append(f"plot written to {plot}")
    return "\n".join(lines), rows


def _import_pymunk():
    try:
        import pymunk
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError("the pymunk cross-check needs pymunk 7: pip install 'pymunk>=7,<8' "
                          "(or the test extra: pip install 'rbimpact[test]')") from exc
    return pymunk


def _pymunk_version():
    return _import_pymunk().version


def _ratios(rows):
    """Speed and error ratios of rbimpact against pymunk (error ratios when rbimpact has
    an error of its own, i.e. against an analytic reference; speed only when rbimpact's
    run is the reference)."""
    rb = rows[-1]
    pm = [r for r in rows if r["engine"] == "pymunk" and math.isfinite(r["error_m"])]
    if not pm or not (rb["error_m"] >= 0) or not rb["run_time_s"] > 0:
        return []
    out = []
    best = min(pm, key=lambda r: r["error_m"])
    picks = [("pymunk's best error on the ladder", best)]
    for r in pm:
        if abs(r["dt_s"] - 1e-4) <= 1e-12 and r is not best:
            picks.append(("pymunk dt = 1e-4 s", r))
    for what, r in picks:
        speed = r["run_time_s"] / rb["run_time_s"]
        if rb["reference"]:
            out.append(f"at {what} ({r['setting']}, error {r['error_m']:.3g} m, "
                       f"{r['run_time_s']:.3g} s): rbimpact's event-driven run (the "
                       f"reference, {rb['run_time_s']:.3g} s) is {speed:.3g} times faster")
            continue
        if rb["error_m"] > 0:
            err = (f"its error {r['error_m'] / rb['error_m']:.3g} times smaller "
                   f"({rb['error_m']:.3g} m"
                   + (", round-off)" if rb["error_m"] < 1e-12 else ")"))
        else:
            err = "its error is 0 at every sample (to round-off)"
        out.append(f"at {what} ({r['setting']}, error {r['error_m']:.3g} m, "
                   f"{r['run_time_s']:.3g} s): rbimpact ({rb['run_time_s']:.3g} s) is "
                   f"{speed:.3g} times faster and {err}")
    return out


_CSV_FIELDS = ("scenario", "law", "engine", "setting", "dt_s", "run_time_s", "error_m",
               "angle_error_rad", "impact_time_error_s", "post_velocity_error_m_s",
               "impacts_matched", "impacts_missed", "impacts_extra", "energy_diff_end_J",
               "reference")


def _write_csv(path, rows):
    import csv
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(_CSV_FIELDS)
        for r in rows:
            w.writerow([repr(r[k]) if isinstance(r[k], float) else r[k] for k in _CSV_FIELDS])


def _plot(path, rows, order, name, law_name, rb_has_error):
    """Log-log plot of error (m) against run time (s): pymunk's ladder and rbimpact."""
    try:
        import matplotlib
        matplotlib.use("Agg", force=False)
        import matplotlib.pyplot as plt
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError("the crosscheck plot needs matplotlib: pip install "
                          "'rbimpact[plot]'") from exc
    pm = [r for r in rows if r["engine"] == "pymunk" and r["error_m"] > 0]
    rb = rows[-1]
    fig, ax = plt.subplots(figsize=(6.4, 4.8))
    if pm:
        ax.loglog([r["run_time_s"] for r in pm], [r["error_m"] for r in pm], "o-",
                  color="C0", label="pymunk (fixed dt)")
        for r in pm:
            ax.annotate(r["setting"], (r["run_time_s"], r["error_m"]),
                        textcoords="offset points", xytext=(5, 5), fontsize=8)
    if rb_has_error and rb["error_m"] > 0:
        y_rb, marker = rb["error_m"], "s"
        label = "rbimpact (event-driven)"
        note = "rbimpact (round-off)" if rb["error_m"] < 1e-12 else "rbimpact"
    else:
        y_rb, marker = ((min(r["error_m"] for r in pm) / 100.0) if pm else 1e-12), "v"
        if rb_has_error:
            label, note = "rbimpact (error 0 to round-off)", "rbimpact: error 0"
        else:
            label, note = "rbimpact (the reference: error 0)", "rbimpact = reference"
    ax.loglog([rb["run_time_s"]], [y_rb], marker, color="C3", ms=9, label=label)
    ax.annotate(note, (rb["run_time_s"], y_rb), textcoords="offset points",
                xytext=(8, 4), fontsize=8)
    ax.set_xlabel("run time (s)")
    ax.set_ylabel("max position error (m, any body)")
    ax.set_title(f"{name} ({law_name}): error against run time\n"
                 f"pymunk observed order of convergence: {_fmt(order, '.2f')}", fontsize=10)
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=8, loc="upper right")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
