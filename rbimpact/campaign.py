"""The randomized drop campaign (issue 13): random scenes over the whole input space, each
checked for the invariants every scene must keep (DESIGN §6c).

    >>> report = drop_campaign(200, dim="both", seed=0)
    >>> print(report.table()); report.ok

Each scene is drawn from its own seed (``scene_seed(dim, seed, index)``), so any scene is
replayed alone by ``rbimpact stability --replay DIM:SCENE_SEED`` (``run_drop(dim,
scene_seed)``). What a scene draws (``draw_scene``):

* a shape: 2D disk, box, convex polygon, rod (segment), capsule, ellipse; 3D sphere, box,
  capsule; its size ``L`` log-uniform in ``[SIZE_MIN, SIZE_MAX]`` m, mass log-uniform in
  [0.01, 100] kg;
* a law (``stability.LAW_VARIANTS``: the five laws, Routh with each termination), ``e`` in
  ``E_VALUES``, ``mu`` in ``MU_VALUES``, ``e_t`` in ``ET_VALUES`` (Brach, C&R);
* the policy for simultaneous contacts: "simultaneous" or "sequential";
* a layout (``LAYOUTS``): a floor; a floor and a wall the body is thrown at; a V-groove
  of two inclined planes; a corner (2D: floor and wall, 3D: floor and two walls); a body
  starting at rest in contact with the floor; two round bodies touching, on the floor;
* the height of the lowest point above the floor, log-uniform in ``[H_MIN, H_MAX]`` m,
  a random orientation, and a velocity and spin of the scale ``sqrt(|g| L)``,
  ``sqrt(|g| / L)``.

The two-body axis (issue 16; ``rbimpact stability --scenes N --dim 2 --bodies 2``, the
same with ``--dim 3``, ``drop_campaign(..., bodies=2)``): two random shapes of the
dimension (random orientations and spin vectors in 3D) thrown at each other in flight
(``draw_pair_scene``: zero gravity and no plane, or gravity with a floor too far below to
reach before ``t_end``), drawn from their own seed stream (``pair_scene_seed``), so the
single-body scenes of a seed are unchanged; checked by ``check_pair_result`` (no overlap
of the bodies beyond the tolerance below, no energy created, momentum kept in zero
gravity; the 3D angular momentum to ``ANGULAR_MOMENTUM_RTOL_3D``). Persistent contact
between bodies is not built (issue 16 item 2): a scene whose
bodies end up rolling or riding on each other stops with the named refusal, a FAIL of a
known open mode.

What is checked (``check_result``), with tolerances scaled to the scene:

* the run ends "done", or with a status that names a real mechanical cause (a Painleve
  inconsistency: ``REFUSED``, shown with its contact); "not supported", stalls, missed
  events, "max_events" and every other error are failures;
* no body below a plane (or two round bodies overlapping) by more than
  ``PEN_RTOL * L + PEN_ATOL`` at densely sampled times (every event, midpoints, a uniform
  grid; each local minimum refined); ``PEN_RTOL_INTEGRATED`` for a scene with integrated
  motion (a pivot phase, 3D flight with general inertia);
* energy: for a law that cannot create energy, the sampled total energy never rises by
  more than ``ENERGY_RTOL * E_scale`` (``ENERGY_RTOL_INTEGRATED`` with integrated motion)
  and no instant's impacts (summed over its cluster)
  gain more than that, with ``E_scale`` the scene's energy above its lowest state (kinetic
  plus ``m |g| (h + L)``). The simultaneous policy's joint Newton solve is not the pair
  law and may create energy for ``e > 0`` (``rbimpact.simulation``): there the check applies
  to scenes whose clusters had a single contact, or ``e == 0``;
* a dissipative scene (``e < 1``, ``mu > 0``, a single floor) that has come to rest by
  ``t_end`` rests in a stable static state: a polygon, rod or box on a face (its centre of
  mass over at least two support points, or a round body), not balanced on a vertex.
"""
import math
import time
from dataclasses import dataclass, replace

import numpy as np

from .errors import NoSolutionError, SimulationError

__all__ = ["draw_scene", "build_scene", "run_drop", "drop_campaign", "scene_seed",
           "draw_pair_scene", "build_pair_scene", "pair_scene_seed",
           "DropRow", "CampaignReport"]

# ---- the input space -------------------------------------------------------------------
E_VALUES = (0.0, 1e-9, 0.3, 0.8, 1.0)
MU_VALUES = (0.0, 0.3, 1.0, 10.0)
ET_VALUES = (0.0, 0.5)
SIZE_MIN, SIZE_MAX = 1e-2, 1.0
"""Body size L (m): log-uniform in this range."""
H_MIN, H_MAX = 1e-12, 0.5
"""Drop height of the lowest point (m): log-uniform in this range."""
SHAPES = {2: ("disk", "box", "polygon", "rod", "capsule", "ellipse"),
          3: ("sphere", "box", "capsule")}
LAYOUTS = ("floor", "floor", "floor", "wall", "groove", "corner", "resting", "touching")
POLICIES = ("simultaneous", "sequential")
GRAVITY = 9.81
T_END_FALLS = 6.0
"""Run time in units of the fall time ``sqrt(2 H_MAX / |g|)`` plus the settling time scale."""
MAX_EVENTS = 200_000
"""Events allowed per scene: reaching it is a failure (a stall in disguise)."""

# ---- tolerances of the checks -----------------------------------------------------------
PEN_RTOL = 1e-9
"""Penetration tolerance relative to the body size L (dimensionless)."""
PEN_ATOL = 1e-12
"""Absolute floor of the penetration tolerance (m)."""
ENERGY_RTOL = 1e-12
"""Energy that a never-gain law may appear to create, relative to the scene's energy scale,
in a scene whose motion is exact (closed-form flight, impacts, rest, slide, roll)."""
ENERGY_RTOL_INTEGRATED = 1e-9
"""The same for a scene with integrated motion (a pivot phase, or 3D flight with general
inertia, or a 2D cluster of bodies in persistent contact: cluster2d pieces ``PIECE_ETOL``
1e-11 M V^2), whose integrators hold energy per step to their own tolerances (2D pivot pieces
``PIECE_ETOL`` 1e-13 m V^2; 3D ``contact_tol`` 1e-10, ``rot_tol`` 1e-12): a long frictionless
3D phase drifts by a few ``contact_tol`` (5e-10 seen on a 3 s capsule slide)."""
PEN_RTOL_INTEGRATED = 1e-7
"""Penetration tolerance relative to L in a scene with integrated motion: the 3D contact
integration holds the contact to ``contact_tol`` (1e-10 L) per step, the 2D pivot pieces to
``PIECE_LTOL`` (1e-10 L); a phase of many steps drifts by their sum (1.1e-8 L seen)."""
REST_SPEED_RTOL = 1e-9
"""A body is at rest at the end when every point moves slower than this times sqrt(|g| L)."""
SUPPORT_RTOL = 1e-7
"""A corner is a support point when its gap is below this times L."""
N_SAMPLES = 4000
"""Uniform samples per scene for the penetration and energy checks (plus every event time
and the midpoints between events)."""
MAX_EVENT_SAMPLES = 20_000
"""At most this many event times (and midpoints) are added to the samples."""



def scene_seed(dim, seed, index):
    """The seed (int) of scene ``index`` of the campaign ``(dim, seed)``."""
    return int(np.random.SeedSequence([int(seed), int(dim), int(index)]).generate_state(1)[0])


def _loguniform(rng, lo, hi):
    return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))


def _draw_law(rng):
    """A law variant and its parameters, drawn from ``rng`` (the first draws of every
    scene): ``(label, law name, params)``."""
    from .stability import LAW_VARIANTS
    label, name, fixed = LAW_VARIANTS[rng.integers(len(LAW_VARIANTS))]
    params = dict(fixed)
    params["e"] = float(E_VALUES[rng.integers(len(E_VALUES))])
    params["mu"] = float(MU_VALUES[rng.integers(len(MU_VALUES))])
    if name in ("brach", "chatterjee_ruina"):
        params["e_t"] = float(ET_VALUES[rng.integers(len(ET_VALUES))])
    return label, name, params


def draw_scene(dim, sseed, planar=False):
    """The parameters of one scene (a plain dict) from its seed ``sseed``. ``planar`` (3D
    only): the same draw made planar (``_make_planar``)."""
    if planar and dim != 3:
        raise ValueError(f"draw_scene: planar scenes are 3D, got dim = {dim!r}")
    rng = np.random.default_rng(sseed)
    label, name, params = _draw_law(rng)
    layout = LAYOUTS[rng.integers(len(LAYOUTS))]
    shapes = SHAPES[dim]
    shape = shapes[rng.integers(len(shapes))]
    if layout == "touching":
        shape = "disk" if dim == 2 else "sphere"
    L = _loguniform(rng, SIZE_MIN, SIZE_MAX)
    aspect = float(rng.uniform(0.2, 1.0))
    h = 0.0 if layout == "resting" else _loguniform(rng, H_MIN, H_MAX)
    spec = dict(dim=dim, seed=int(sseed), law=label, law_name=name, params=params,
                policy=POLICIES[rng.integers(2)], layout=layout, shape=shape, size=L,
                aspect=aspect, mass=_loguniform(rng, 1e-2, 1e2), height=h)
    if shape == "polygon":
        spec["vertices"] = _polygon_vertices(rng, L, aspect)
    vs = math.sqrt(GRAVITY * L)
    ws = math.sqrt(GRAVITY / L)
    if layout == "resting":
        spec["velocity"] = [0.0] * dim
        spec["spin"] = [0.0] * (1 if dim == 2 else 3)
    else:
        spec["velocity"] = [float(x) for x in rng.uniform(-1.0, 1.0, dim) * vs]
        spec["spin"] = [float(x) for x in rng.uniform(-3.0, 3.0, 1 if dim == 2 else 3) * ws]
    if dim == 2:
        spec["angle"] = float(rng.uniform(0, 2 * math.pi))
        if layout == "resting":
            spec["angle"] = 0.0
    else:
        q = rng.normal(size=4)
        spec["orientation"] = [float(x) for x in q / np.linalg.norm(q)]
        if layout == "resting":     # on a face; a capsule on its side (axis along x)
            h = math.sqrt(0.5)
            spec["orientation"] = ([h, 0.0, h, 0.0] if shape == "capsule"
                                   else [1.0, 0.0, 0.0, 0.0])
    spec["tilt"] = float(rng.uniform(0.2, 1.2))      # groove half-opening (rad from level)
    if planar:
        _make_planar(spec)
    return spec


PLANAR_STREAM = 7
"""Second word of the generator seed of a planar scene's pitch angle (``_make_planar``)."""


def _make_planar(spec):
    """The 3D draw made planar, in place: orientation a rotation about y by an angle drawn
    from ``(seed, PLANAR_STREAM)`` (a resting body keeps its face or side down), velocity in
    the xz plane, spin about y. The motion stays in the plane: exact zeros (a symmetric
    contact force, a slip along x, F(phi0) = 0 in a slip-direction scan) where a random
    draw has round-off, so a decision on the sign of round-off shows (the thin capsule
    falling over of session 14 was such a scene)."""
    spec["planar"] = True
    if spec["layout"] != "resting":
        th = float(np.random.default_rng([spec["seed"], PLANAR_STREAM]).uniform(0.0,
                                                                                 2 * math.pi))
        spec["orientation"] = [math.cos(0.5 * th), 0.0, math.sin(0.5 * th), 0.0]
    spec["velocity"][1] = 0.0
    spec["spin"] = [0.0, spec["spin"][1], 0.0]


def _polygon_vertices(rng, L, aspect):
    """A random convex polygon of 3 to 7 corners on an ellipse of axes ``L/2``,
    ``aspect L/2`` (m), consecutive corners at least 0.3 rad apart (in angle)."""
    k = int(rng.integers(3, 8))
    ang = np.sort(rng.uniform(0, 2 * math.pi, k))
    while np.min(np.diff(np.r_[ang, ang[0] + 2 * math.pi])) < 0.3:
        ang = np.sort(rng.uniform(0, 2 * math.pi, k))
    return [(0.5 * L * math.cos(a), 0.5 * L * aspect * math.sin(a)) for a in ang]


def _shape(spec):
    L, a, dim = spec["size"], spec["aspect"], spec["dim"]
    s = spec["shape"]
    if dim == 2:
        from .shapes import Box, Disk, Ellipse, Polygon, Rod
        if s == "disk":
            return Disk(0.5 * L)
        if s == "box":
            return Box(L, a * L)
        if s == "polygon":
            return Polygon(spec["vertices"])
        if s == "rod":
            return Rod(L)
        if s == "capsule":
            return Rod(L, 0.5 * a * L)
        return Ellipse(0.5 * L, 0.5 * a * L)
    from .shapes3d import Box3D, Capsule, Sphere
    if s == "sphere":
        return Sphere(0.5 * L)
    if s == "box":
        return Box3D((L, a * L, (0.5 + 0.5 * a) * L))
    return Capsule(L, 0.5 * a * L)


def build_scene(spec):
    """``(simulation, t_end, max_events)`` for a drawn scene."""
    from .laws import Law
    from .simulation import Simulation
    dim, L, layout = spec["dim"], spec["size"], spec["layout"]
    shape = _shape(spec)
    law = Law(spec["law_name"], **spec["params"])
    if dim == 2:
        from .scene import Scene2D
        scene = Scene2D(gravity=(0.0, -GRAVITY))
        pose = dict(angle=spec["angle"], velocity=spec["velocity"],
                    angular_velocity=spec["spin"][0])
        up = np.array([0.0, 1.0])
    else:
        from .scene3d import Scene3D
        scene = Scene3D(gravity=(0.0, 0.0, -GRAVITY))
        pose = dict(orientation=spec["orientation"], velocity=spec["velocity"],
                    angular_velocity=spec["spin"])
        up = np.array([0.0, 0.0, 1.0])
    # planes: the floor through the origin, and walls just beside the body
    R = shape.bounding_radius
    if layout == "groove":
        tl = spec["tilt"]
        for sgn in (1.0, -1.0):
            n = np.zeros(dim)
            n[0] = -sgn * math.sin(tl)
            n[-1] = math.cos(tl)
            scene.add_plane(np.zeros(dim), n)
    else:
        scene.add_plane(np.zeros(dim), up)
    if layout in ("wall", "corner"):
        gapw = 0.0 if layout == "corner" else 0.5 * R
        p = np.zeros(dim)
        p[0] = -(R + gapw)
        n = np.zeros(dim)
        n[0] = 1.0
        scene.add_plane(p, n)
        if layout == "corner" and dim == 3:
            p = np.zeros(3)
            p[1] = -R
            scene.add_plane(p, (0.0, 1.0, 0.0))
        v = np.array(pose["velocity"], float)
        v[0] = -abs(v[0])          # thrown at the wall
        pose["velocity"] = v
    mass = spec["mass"]
    # place the body so that its lowest point is `height` above every plane
    pos = np.zeros(dim)
    body = scene.add_body(shape, mass, pos, **pose)
    b = scene.bodies[body]
    lift = 0.0
    for pl in scene.planes:
        lift = max(lift, _needed_lift(scene, b, pl, dim))
    pos[-1] = lift + spec["height"]
    scene.bodies[body] = replace(b, position=tuple(float(x) for x in pos))
    if layout == "touching":   # a second round body touching the first, on the floor
        r = 0.5 * L
        r2 = 0.5 * L * (0.5 + spec["aspect"])
        other = _shape_round(dim, r2)
        ang = 0.3 + 0.9 * spec["aspect"]
        d = r + r2
        pos2 = pos.copy()
        pos2[0] += d * math.cos(ang)
        pos2[-1] += d * math.sin(ang)
        kw = dict(velocity=[0.0] * dim)
        scene.add_body(other, mass * spec["aspect"], pos2, **kw)
    sim = Simulation(scene, law, policy=spec["policy"])
    fall = math.sqrt(2.0 * H_MAX / GRAVITY)
    t_end = T_END_FALLS * fall + 20.0 * math.sqrt(L / GRAVITY)
    return sim, t_end, MAX_EVENTS


def _shape_round(dim, r):
    if dim == 2:
        from .shapes import Disk
        return Disk(r)
    from .shapes3d import Sphere
    return Sphere(r)


def _needed_lift(scene, body, plane, dim):
    """How far the body (centre at the origin) must rise along the up axis for its lowest
    point to touch ``plane`` (m)."""
    n = np.asarray(plane.normal, float)
    if dim == 2:
        from .simulation import _min_gap_plane
    else:
        from .simulation3d import _min_gap_plane
    g = _min_gap_plane(body, plane)      # gap at the origin
    nz = n[-1]
    if nz <= 1e-12:
        return 0.0
    return max(0.0, -g / nz)


# ============================================================================================
# checks
# ============================================================================================
@dataclass
class DropRow:
    """One scene of the campaign: what was drawn, how it ended and what the checks found.
    ``verdict``: "OK", "REFUSED" (a real mechanical cause, named in ``note``) or "FAIL"."""

    dim: int
    seed: int
    shape: str
    law: str
    layout: str
    policy: str
    e: float
    mu: float
    height: float
    verdict: str
    status: str
    impacts: int
    penetration: float
    pen_tol: float
    energy_gain: float
    wall: float
    note: str
    planar: bool = False

    @property
    def reproducer(self):
        extra = (" --bodies 2" if self.layout in PAIR_LAYOUTS else
                 f" --bodies {STACK_BODIES}" if self.layout == STACK_LAYOUT else "")
        extra += " --planar" if self.planar else ""
        return f"rbimpact stability --replay {self.dim}:{self.seed}{extra}"

    FIELDS = ("dim", "seed", "shape", "law", "layout", "policy", "e", "mu", "height",
              "verdict", "status", "impacts", "penetration", "pen_tol", "energy_gain",
              "wall", "note")

    def fields(self):
        return [getattr(self, k) for k in self.FIELDS] + [self.reproducer]


def _sample_times(res, n):
    t0, t1 = res.t_start, res.t_end
    ev = np.asarray(res.events["t"])[:MAX_EVENT_SAMPLES]
    mids = 0.5 * (ev[1:] + ev[:-1])
    t = np.concatenate([np.linspace(t0, t1, n), ev, mids, ev + 1e-9 * (t1 - t0 + 1.0)])
    return np.unique(np.clip(t, t0, t1))


def _supports(sim, s, k, dim, L):
    """Support analysis of body 0 on plane 0 at sample ``k``: (number of corners within
    SUPPORT_RTOL L of the plane, whether the centre of mass is over them, rounded)."""
    from .stability import _quat_rotate
    body = sim.scene.bodies[0]
    sh = body.shape
    name = type(sh).__name__
    n = np.asarray(sim.scene.planes[0].normal, float)
    tol = SUPPORT_RTOL * L
    if dim == 2:
        x = np.array([s["x"][k, 0], s["y"][k, 0]])
        th = s["angle"][k, 0]
        c, sn = math.cos(th), math.sin(th)
        if name == "Disk":
            return 1, True
        if name == "Ellipse":
            nb = np.array([c * n[0] + sn * n[1], -sn * n[0] + c * n[1]])
            h = math.sqrt(sh.a ** 2 * nb[0] ** 2 + sh.b ** 2 * nb[1] ** 2)
            return 1, h <= min(sh.a, sh.b) + tol
        V = np.asarray(sh.vertices)
        rad = getattr(sh, "radius", 0.0)
        P = x + V @ np.array([[c, sn], [-sn, c]])
        gaps = P @ n - rad - sim.scene.planes[0].offset
        sup = P[gaps < tol]
        if len(sup) < 2:
            return len(sup), False
        t = np.array([n[1], -n[0]])
        u = sup @ t
        xc = x @ t
        return len(sup), bool(u.min() - tol <= xc <= u.max() + tol)
    pos = s["position"][k, 0]
    if name == "Sphere":
        return 1, True
    if name == "Box3D":
        V, rad = np.asarray(sh.vertices), 0.0
    else:
        V, rad = np.array([[0, 0, -0.5 * sh.length], [0, 0, 0.5 * sh.length]]), sh.radius
    q = np.repeat(s["orientation"][k, 0][None], len(V), axis=0)
    P = pos + _quat_rotate(q, V)
    gaps = P @ n - rad - sim.scene.planes[0].offset
    cnt = int(np.sum(gaps < tol))
    need = 3 if name == "Box3D" else 2
    return cnt, cnt >= need


def check_result(spec, sim, res, note):
    """The invariants of one finished (or partial) run. Returns
    ``(problems, penetration, pen_tol, energy_gain)``: ``problems`` a list of strings."""
    from .kernels.codes import PM_CLUSTER
    from .stability import (NEVER_GAIN, _energy_from_sample, _gaps_2d, _gaps_3d, _refine,
                            kinetic_from_sample)
    dim, L = spec["dim"], spec["size"]
    problems = []
    if res is None or res.t_end <= res.t_start:
        return problems, 0.0, 0.0, 0.0
    t = _sample_times(res, N_SAMPLES)
    s = res.sample(t)
    gaps = (_gaps_2d if dim == 2 else _gaps_3d)(sim, s)
    ev = res.events
    # integrated motion: a pivot phase, a cluster of bodies in persistent contact
    # (PM_CLUSTER: a "contact" event of mode PM_CLUSTER), 3D general inertia
    integrated = bool(np.any(ev["kind"] == "pivot")) or bool(
        np.any((ev["kind"] == "contact") & (ev["mode"] == PM_CLUSTER))) or (
        dim == 3 and spec["shape"] != "sphere")
    pen_tol = (PEN_RTOL_INTEGRATED if integrated else PEN_RTOL) * L + PEN_ATOL
    worst = 0.0
    for key, g in gaps.items():
        gmin = float(g.min())
        if gmin < 0.1 * pen_tol:
            gmin = _refine(res, sim, dim, key, t, g)
        if -gmin > worst:
            worst = -gmin
            wkey = key
    if worst > pen_tol:
        problems.append(f"penetration {worst:.3g} m > {pen_tol:.2g} m (body {wkey[0]} "
                        f"in {wkey[1]} {wkey[2]})")
    # energy
    E = _energy_from_sample(res, s, dim)
    K0 = float(kinetic_from_sample(res, s, dim)[0])
    g = GRAVITY
    if dim == 2:
        heights = s["y"][0]
    else:
        heights = s["position"][0, :, 2]
    E_scale = K0 + float(np.sum(res.masses * g * (np.abs(heights) + L)))
    gain = float(np.max(E - np.minimum.accumulate(E))) / E_scale
    ev = res.events
    imp = ev[ev["kind"] == "impact"]
    if len(imp):
        _, inv = np.unique(imp["t"], return_inverse=True)
        gain = max(gain, float(np.bincount(inv, weights=imp["dE"]).max()) / E_scale)
    joint = spec["policy"] == "simultaneous" and len(imp) and np.any(imp["cluster"] > 1)
    safe = spec["law"] in NEVER_GAIN and (not joint or spec["params"]["e"] == 0.0)
    etol = ENERGY_RTOL_INTEGRATED if integrated else ENERGY_RTOL
    if safe and gain > etol:
        problems.append(f"energy created: {gain:.3g} of the scene's energy scale "
                        f"{E_scale:.3g} J (> {etol:g})")
    # a dissipative scene at rest must rest stably
    p = spec["params"]
    if (res.status == "done" and p["e"] < 1.0 and p["mu"] > 0.0
            and spec["layout"] in ("floor", "resting")):
        vs = math.sqrt(GRAVITY * L)
        R = sim.scene.bodies[0].shape.bounding_radius
        if dim == 2:
            speed = math.hypot(s["vx"][-1, 0], s["vy"][-1, 0]) + abs(s["omega"][-1, 0]) * R
        else:
            speed = (float(np.linalg.norm(s["velocity"][-1, 0]))
                     + float(np.linalg.norm(s["angular_velocity"][-1, 0])) * R)
        if speed < REST_SPEED_RTOL * vs:
            cnt, stable = _supports(sim, s, -1, dim, L)
            if not stable:
                problems.append(f"at rest in an unstable state ({cnt} support point(s))")
        else:
            note.append(f"still moving at t_end ({speed:.2g} m/s)")
    return problems, worst, pen_tol, gain


# ============================================================================================
# the two-body axis (issue 16 item 5): two random shapes thrown at each other, in flight
# ============================================================================================
PAIR_LAYOUTS = ("pair-free", "pair-high")
"""Layouts of the two-body axis: "pair-free" zero gravity, no plane; "pair-high" gravity,
and a floor far enough below that nothing lands before ``t_end`` (the bodies fall
together; their relative motion is the same)."""
PAIR_STREAM = 2
"""Extra word of the seed sequence of a two-body scene (``pair_scene_seed``): its seeds are
a stream apart from the single-body scenes', which draw exactly as before."""
PAIR_GAP = (1e-9, 1.0)
"""Initial gap of the bounding circles, relative to the sum of their radii: log-uniform."""
PAIR_FAST_SPIN = 0.2
"""Probability that a body spins 30 times faster (spins up to 90 sqrt(|g| / L) rad/s)."""
MOMENTUM_RTOL = 1e-12
"""Linear and angular momentum (about the origin) kept in a zero-gravity scene, relative to
the scene's scales ``sum m |v|`` and ``sum I |w| + m |x| |v|``, at the end of the run."""
ANGULAR_MOMENTUM_RTOL_3D = 1e-9
"""The same for the angular momentum of a 3D scene: a body with three different moments
rotates by an integrator held to ``rot_tol`` (1e-12) per step, so its angular momentum
drifts by a few ``rot_tol`` per unit of ``|w| t``."""
ANGULAR_MOMENTUM_RTOL_CLUSTER = 1e-9
"""The same for a 2D two-body scene whose bodies were in persistent contact (a cluster,
integrated by ``cluster2d`` to ``CLUSTER_TOL`` 1e-12 per step, its positions projected
back onto the contacts: the linear momentum stays exact, the angular momentum drifts by
the integrator's error)."""


def pair_scene_seed(dim, seed, index):
    """The seed (int) of two-body scene ``index`` of the campaign ``(dim, seed)``."""
    return int(np.random.SeedSequence([int(seed), int(dim), int(index), PAIR_STREAM])
               .generate_state(1)[0])


def draw_pair_scene(dim, sseed):
    """The parameters of one two-body scene (a plain dict) from its seed ``sseed``: two
    shapes of ``SHAPES[2]`` (sizes, aspects, masses as the single-body scenes), a law, e,
    mu, e_t and a policy as ``draw_scene``, a layout of ``PAIR_LAYOUTS``; B placed from A
    along a random direction with a gap of the bounding circles ``PAIR_GAP`` (relative),
    thrown at A with an impact parameter up to 0.8 of the bounding radii, a closing speed
    of 0.2 to 2 ``sqrt(|g| L)``, random angles and spins."""
    if dim not in (2, 3):
        raise ValueError(f"the two-body campaign axis has dim 2 or 3; got dim={dim!r}")
    rng = np.random.default_rng(sseed)
    label, name, params = _draw_law(rng)
    layout = PAIR_LAYOUTS[rng.integers(len(PAIR_LAYOUTS))]
    bodies = []
    for _ in range(2):
        shape = SHAPES[dim][rng.integers(len(SHAPES[dim]))]
        L = _loguniform(rng, SIZE_MIN, SIZE_MAX)
        aspect = float(rng.uniform(0.2, 1.0))
        b = dict(shape=shape, size=L, aspect=aspect, mass=_loguniform(rng, 1e-2, 1e2))
        if dim == 2:
            b["angle"] = float(rng.uniform(0, 2 * math.pi))
            if shape == "polygon":
                b["vertices"] = _polygon_vertices(rng, L, aspect)
            w = float(rng.uniform(-3.0, 3.0)) * math.sqrt(GRAVITY / L)
        else:
            q = rng.normal(size=4)
            b["orientation"] = tuple(float(x) for x in q / np.linalg.norm(q))
            w = rng.uniform(-3.0, 3.0, size=3) * math.sqrt(GRAVITY / L)
        if rng.uniform() < PAIR_FAST_SPIN:
            w = w * 30.0
        b["spin"] = w if dim == 2 else tuple(float(x) for x in w)
        bodies.append(b)
    Lm = math.sqrt(bodies[0]["size"] * bodies[1]["size"])
    if dim == 2:
        direction = float(rng.uniform(0, 2 * math.pi))
    else:
        u = rng.normal(size=3)
        direction = tuple(float(x) for x in u / np.linalg.norm(u))
    spec = dict(dim=dim, seed=int(sseed), law=label, law_name=name, params=params,
                policy=POLICIES[rng.integers(2)], layout=layout,
                shape="+".join(b["shape"] for b in bodies), size=min(b["size"] for b in bodies),
                bodies=bodies, height=0.0, direction=direction,
                gap=_loguniform(rng, *PAIR_GAP), impact=float(rng.uniform(-0.8, 0.8)),
                speed=float(rng.uniform(0.2, 2.0)) * math.sqrt(GRAVITY * Lm))
    if dim == 3:        # the side of the impact parameter: a unit vector normal to u
        p = np.cross(u, rng.normal(size=3))
        spec["side"] = tuple(float(x) for x in p / np.linalg.norm(p))
    return spec


def build_pair_scene(spec):
    """``(simulation, t_end, max_events)`` for a drawn two-body scene: A at the origin, B
    at ``(R_A + R_B) (1 + gap)`` along ``direction`` (bounding radii ``R``), moving toward
    A's side with ``speed`` and an impact parameter ``impact (R_A + R_B)``; each body's
    centre of mass velocity is such that the total momentum is zero. ``t_end``: the time to
    close the distance and pass through twice the bounding radii."""
    from .laws import Law
    dim = spec["dim"]
    law = Law(spec["law_name"], **spec["params"])
    shapes = [_shape(dict(b, dim=dim)) for b in spec["bodies"]]
    R = [sh.bounding_radius for sh in shapes]
    m = [b["mass"] for b in spec["bodies"]]
    if dim == 3:
        return _build_pair_scene_3d(spec, law, shapes, R, m)
    from .scene import Scene2D
    from .simulation import Simulation
    u = np.array([math.cos(spec["direction"]), math.sin(spec["direction"])])
    perp = np.array([-u[1], u[0]])
    d = (R[0] + R[1]) * (1.0 + spec["gap"])
    xB = d * u + spec["impact"] * (R[0] + R[1]) * perp
    vrel = -spec["speed"] * u           # B relative to A
    vA = -m[1] / (m[0] + m[1]) * vrel
    vB = m[0] / (m[0] + m[1]) * vrel
    free = spec["layout"] == "pair-free"
    scene = Scene2D(gravity=(0.0, 0.0) if free else (0.0, -GRAVITY))
    t_end = (d + 2.0 * (R[0] + R[1])) / spec["speed"]
    if not free:    # a floor far below: nothing lands before t_end (no body's centre
        # moves faster than sqrt(2 K / m) relative to free fall, K the kinetic energy)
        K = sum(0.5 * mi * float(v @ v) + 0.5 * sh.moment(mi) * b["spin"] ** 2
                for sh, mi, b, v in zip(shapes, m, spec["bodies"], (vA, vB)))
        drop = 0.5 * GRAVITY * t_end ** 2 + 2.0 * math.sqrt(2.0 * K / min(m)) * t_end
        scene.add_floor(-(drop + 2.0 * (R[0] + R[1]) + d + 1.0))
    for sh, mass, b, x, v in zip(shapes, m, spec["bodies"], (np.zeros(2), xB), (vA, vB)):
        scene.add_body(sh, mass, tuple(x), angle=b["angle"], velocity=tuple(v),
                       angular_velocity=b["spin"])
    sim = Simulation(scene, law, policy=spec["policy"])
    return sim, t_end, MAX_EVENTS


def _build_pair_scene_3d(spec, law, shapes, R, m):
    """``build_pair_scene`` in 3D: the same placement along the unit ``direction`` with the
    impact parameter along ``side``; random orientations and spin vectors."""
    from .scene3d import Scene3D
    from .simulation3d import Simulation3D
    u = np.asarray(spec["direction"], float)
    perp = np.asarray(spec["side"], float)
    d = (R[0] + R[1]) * (1.0 + spec["gap"])
    xB = d * u + spec["impact"] * (R[0] + R[1]) * perp
    vrel = -spec["speed"] * u
    vA = -m[1] / (m[0] + m[1]) * vrel
    vB = m[0] / (m[0] + m[1]) * vrel
    free = spec["layout"] == "pair-free"
    scene = Scene3D(gravity=(0.0, 0.0, 0.0) if free else (0.0, 0.0, -GRAVITY))
    t_end = (d + 2.0 * (R[0] + R[1])) / spec["speed"]
    if not free:
        K = 0.0
        for sh, mi, b, v in zip(shapes, m, spec["bodies"], (vA, vB)):
            w = np.asarray(b["spin"], float)
            K += 0.5 * mi * float(v @ v) + 0.5 * float(np.max(sh.inertia(mi))) * float(w @ w)
        drop = 0.5 * GRAVITY * t_end ** 2 + 2.0 * math.sqrt(2.0 * K / min(m)) * t_end
        scene.add_floor(-(drop + 2.0 * (R[0] + R[1]) + d + 1.0))
    for sh, mass, b, x, v in zip(shapes, m, spec["bodies"], (np.zeros(3), xB), (vA, vB)):
        scene.add_body(sh, mass, tuple(x), orientation=b["orientation"], velocity=tuple(v),
                       angular_velocity=b["spin"])
    sim = Simulation3D(scene, law, policy=spec["policy"])
    return sim, t_end, MAX_EVENTS


# ============================================================================================
# the stack axis (issue 16 items 2 and 5): three random shapes dropped onto each other
# ============================================================================================
STACK_LAYOUT = "stack"
"""Layout of the stack axis: a floor, three bodies released at rest one above the other."""
STACK_STREAM = 3
"""Extra word of the seed sequence of a stack scene (``stack_scene_seed``)."""
STACK_BODIES = 3
STACK_SIZE = (0.05, 0.5)
"""Sizes (m) of the stacked bodies, log-uniform: within a factor 10 of one another."""
STACK_GAP = (1e-6, 0.1)
"""Drop height (m) of each body above the bounding circle of the one below (the lowest:
above the floor), log-uniform."""
STACK_OFFSET = 0.3
"""Lateral offset of each body from the one below, uniform within +- this times the
lower body's size."""
STACK_TILT = 0.3
"""Tilt (rad) of a box, rod or capsule from lying flat, uniform within +- this (polygons
and ellipses: any angle)."""
STACK_SETTLE = 1.0
"""Time (s) a stack scene runs past the top body's free-fall time to the floor."""


def stack_scene_seed(dim, seed, index):
    """The seed (int) of stack scene ``index`` of the campaign ``(dim, seed)``."""
    return int(np.random.SeedSequence([int(seed), int(dim), int(index), STACK_STREAM])
               .generate_state(1)[0])


def draw_stack_scene(dim, sseed):
    """The parameters of one stack scene (2D; a plain dict) from its seed ``sseed``: a law,
    e, mu, e_t and a policy as ``draw_scene``; three shapes of ``SHAPES[2]``, sizes in
    ``STACK_SIZE``, aspects 0.3 to 1, masses 0.1 to 10 kg (log-uniform), each released at
    rest ``STACK_GAP`` above the one below, offset sideways by up to ``STACK_OFFSET`` of
    the lower body's size, tilted by up to ``STACK_TILT``."""
    if dim != 2:
        raise ValueError(f"the stack campaign axis is 2D (dim 2); got dim={dim!r}")
    rng = np.random.default_rng(sseed)
    label, name, params = _draw_law(rng)
    bodies = []
    for _ in range(STACK_BODIES):
        shape = SHAPES[2][rng.integers(len(SHAPES[2]))]
        L = _loguniform(rng, *STACK_SIZE)
        aspect = float(rng.uniform(0.3, 1.0))
        b = dict(shape=shape, size=L, aspect=aspect, mass=_loguniform(rng, 0.1, 10.0),
                 gap=_loguniform(rng, *STACK_GAP),
                 offset=float(rng.uniform(-STACK_OFFSET, STACK_OFFSET)))
        if shape in ("polygon", "ellipse"):
            b["angle"] = float(rng.uniform(0, 2 * math.pi))
        else:
            b["angle"] = float(rng.uniform(-STACK_TILT, STACK_TILT))
        if shape == "polygon":
            b["vertices"] = _polygon_vertices(rng, L, aspect)
        bodies.append(b)
    return dict(dim=dim, seed=int(sseed), law=label, law_name=name, params=params,
                policy=POLICIES[rng.integers(2)], layout=STACK_LAYOUT,
                shape="+".join(b["shape"] for b in bodies),
                size=min(b["size"] for b in bodies), bodies=bodies, height=bodies[0]["gap"])


def build_stack_scene(spec):
    """``(simulation, t_end, max_events)`` for a drawn stack scene: a floor at y = 0, body
    k's centre ``gap_k + R_k`` above the top of body k - 1's bounding circle (R the
    bounding radius), ``offset_k`` times body k - 1's size to the side; ``t_end`` the top
    body's free-fall time to the floor plus ``STACK_SETTLE``."""
    from .laws import Law
    from .scene import Scene2D
    from .simulation import Simulation
    law = Law(spec["law_name"], **spec["params"])
    scene = Scene2D(gravity=(0.0, -GRAVITY))
    scene.add_floor(0.0)
    top, x, below = 0.0, 0.0, None
    for b in spec["bodies"]:
        sh = _shape(dict(b, dim=2))
        R = sh.bounding_radius
        if below is not None:
            x += b["offset"] * below
        y = top + b["gap"] + R
        scene.add_body(sh, b["mass"], (x, y), angle=b["angle"])
        top, below = y + R, b["size"]
    t_end = math.sqrt(2.0 * top / GRAVITY) + STACK_SETTLE
    return Simulation(scene, law, policy=spec["policy"]), t_end, MAX_EVENTS


def check_stack_result(spec, sim, res, note):
    """The invariants of a stack scene: ``check_result``'s (no body below the floor, no
    energy created by a law that cannot create it), and no two bodies overlapping by more
    than its tolerance (``pair_gap`` at the sampled times, local minima refined).
    Returns ``(problems, penetration, pen_tol, energy_gain)``."""
    problems, worst, pen_tol, gain = check_result(spec, sim, res, note)
    if res is None or res.t_end <= res.t_start:
        return problems, worst, pen_tol, gain
    t = _sample_times(res, N_SAMPLES)
    s = res.sample(t)
    n = len(spec["bodies"])
    for i in range(n):
        for j in range(i + 1, n):
            gmin = _worst_pair_gap(sim, res, t, s, i, j, 4)
            if -gmin > worst:
                worst = -gmin
                if worst > pen_tol:
                    problems.append(f"penetration {worst:.3g} m > {pen_tol:.2g} m (body {j} "
                                    f"in body {i})")
    return problems, worst, pen_tol, gain


def _worst_pair_gap(sim, res, t, s, i, j, n_minima):
    """The smallest gap (m) of bodies i and j over a run: ``pair_gap`` at the sampled
    times ``t`` (states ``s``), each of its ``n_minima`` smallest local minima refined by a
    bounded minimisation between the neighbouring samples (a sampled dip can miss its
    bottom)."""
    from .stability import refine_minima
    g = np.array([pair_gap(sim, s, k, i, j) for k in range(len(t))])
    return refine_minima(t, g, lambda tt: pair_gap(sim, res.sample([tt]), 0, i, j), n_minima)


def pair_gap(sim, s, k, i=0, j=1):
    """Signed gap (m) of bodies i and j at sample ``k`` of ``s`` (``Result.sample``):
    ``kernels.pair2d.frame_rel`` (3D: ``kernels.pair3d.pair_frame``; distance when apart,
    minus the penetration depth)."""
    if "position" in s:
        return _pair_gap_3d(sim, s, k, i, j)
    from .kernels.pair2d import frame_rel
    bint, bflt, V = sim._bint, sim._bflt, sim._verts
    return float(frame_rel(int(bint[i, 0]), bflt[i, 2], bflt[i, 3], bflt[i, 4], V,
                           int(bint[i, 1]), int(bint[i, 2]), float(s["angle"][k, i]),
                           int(bint[j, 0]), bflt[j, 2], bflt[j, 3], bflt[j, 4], V,
                           int(bint[j, 1]), int(bint[j, 2]),
                           float(s["x"][k, j] - s["x"][k, i]),
                           float(s["y"][k, j] - s["y"][k, i]), float(s["angle"][k, j]))[0])


def _pair_gap_3d(sim, s, k, i, j):
    from .kernels.pair3d import N_FE, N_FR, pair_frame
    rows = []
    for b in (i, j):
        row = np.zeros(19)
        row[0:3] = s["position"][k, b]
        row[3:7] = s["orientation"][k, b]
        rows.append(row)
    bint, bflt = sim._bint, sim._bflt
    return float(pair_frame(int(bint[i, 0]), *bflt[i, 4:8], rows[0], int(bint[j, 0]),
                            *bflt[j, 4:8], rows[1], np.zeros(N_FR), np.zeros(N_FE, np.int64)))


def _momenta(res, s, dim, k):
    """Linear momentum (kg m/s, a vector) and angular momentum about the origin (kg m^2/s,
    a scalar in 2D, a vector in 3D) of sample ``k``."""
    m = res.masses
    if dim == 2:
        x, y, vx, vy, w = (s[c][k] for c in ("x", "y", "vx", "vy", "omega"))
        return (np.array([np.sum(m * vx), np.sum(m * vy)]),
                np.array([np.sum(res.moments * w + m * (x * vy - y * vx))]))
    from .stability import _quat_rotate
    x, v = s["position"][k], s["velocity"][k]
    q, w = s["orientation"][k], s["angular_velocity"][k]
    qc = q * np.array([1.0, -1.0, -1.0, -1.0])
    Iw = _quat_rotate(q, res.inertias * _quat_rotate(qc, w))     # world I w
    return (np.sum(m[:, None] * v, axis=0),
            np.sum(Iw + m[:, None] * np.cross(x, v), axis=0))


def _momentum_scales(res, s, dim):
    """``sum m |v|`` and ``sum |I w| + m |x| |v|`` at the first sample."""
    m = res.masses
    if dim == 2:
        x, y, vx, vy, w = (s[c][0] for c in ("x", "y", "vx", "vy", "omega"))
        return (float(np.sum(m * np.hypot(vx, vy))),
                float(np.sum(res.moments * np.abs(w) + m * np.hypot(x, y) * np.hypot(vx, vy))))
    x, v, w = s["position"][0], s["velocity"][0], s["angular_velocity"][0]
    speed = np.linalg.norm(v, axis=1)
    Imax = np.max(res.inertias, axis=1)
    return (float(np.sum(m * speed)),
            float(np.sum(Imax * np.linalg.norm(w, axis=1)
                         + m * np.linalg.norm(x, axis=1) * speed)))


def check_pair_result(spec, sim, res, note):
    """The invariants of a two-body scene (as ``check_result``): the bodies never overlap
    by more than ``PEN_RTOL L + PEN_ATOL`` (``L`` the smaller size; sampled gaps, local
    minima refined), no energy created by a law that cannot create it (beyond
    ``ENERGY_RTOL`` of ``K0 + sum m |g| L``), and in zero gravity the linear and angular
    momentum kept to ``MOMENTUM_RTOL``. Returns ``(problems, penetration, pen_tol,
    energy_gain)``."""
    from .kernels.codes import PM_CLUSTER
    from .stability import NEVER_GAIN, _energy_from_sample, kinetic_from_sample
    problems = []
    if res is None or res.t_end <= res.t_start:
        return problems, 0.0, 0.0, 0.0
    L = spec["size"]
    ev = res.events
    # integrated motion: a cluster of the two bodies in persistent contact (as check_result)
    cluster = bool(np.any((ev["kind"] == "contact") & (ev["mode"] == PM_CLUSTER)))
    pen_tol = (PEN_RTOL_INTEGRATED if cluster else PEN_RTOL) * L + PEN_ATOL
    t = _sample_times(res, N_SAMPLES)
    s = res.sample(t)
    worst = _worst_pair_gap(sim, res, t, s, 0, 1, 8)
    pen = max(0.0, -worst)
    if pen > pen_tol:
        problems.append(f"penetration {pen:.3g} m > {pen_tol:.2g} m (body 0 in body 1)")
    dim = spec["dim"]
    E = _energy_from_sample(res, s, dim)
    K0 = float(kinetic_from_sample(res, s, dim)[0])
    gabs = float(np.linalg.norm(sim.scene.gravity))
    sizes = np.array([b["size"] for b in spec["bodies"]])
    up = s["y"] if dim == 2 else s["position"][:, :, 2]
    E_scale = K0 + float(np.sum(res.masses * gabs * (np.max(np.abs(up), axis=0) + sizes)))
    gain = float(np.max(E - np.minimum.accumulate(E))) / E_scale
    imp = ev[ev["kind"] == "impact"]
    if len(imp):
        _, inv = np.unique(imp["t"], return_inverse=True)
        gain = max(gain, float(np.bincount(inv, weights=imp["dE"]).max()) / E_scale)
    joint = spec["policy"] == "simultaneous" and len(imp) and np.any(imp["cluster"] > 1)
    safe = spec["law"] in NEVER_GAIN and (not joint or spec["params"]["e"] == 0.0)
    # a 3D box has three different moments: its rotation is integrated (rot_tol), as in
    # the drop scenes (check_result)
    etol = (ENERGY_RTOL_INTEGRATED if (dim == 3 and "box" in spec["shape"]) or cluster
            else ENERGY_RTOL)
    if safe and gain > etol:
        problems.append(f"energy created: {gain:.3g} of the scene's energy scale "
                        f"{E_scale:.3g} J (> {etol:g})")
    if spec["layout"] == "pair-free":
        p0, L0 = _momenta(res, s, dim, 0)
        p1, L1 = _momenta(res, s, dim, len(t) - 1)
        ps, Ls = _momentum_scales(res, s, dim)
        dp = float(np.max(np.abs(p1 - p0)))
        dL = float(np.max(np.abs(L1 - L0)))
        # a general 3D rotation is integrated to rot_tol: angular momentum to its accuracy
        ltol = (ANGULAR_MOMENTUM_RTOL_3D if dim == 3 else
                ANGULAR_MOMENTUM_RTOL_CLUSTER if cluster else MOMENTUM_RTOL)
        if dp > MOMENTUM_RTOL * ps or dL > ltol * Ls:
            problems.append(f"momentum not kept: linear {dp:.3g} of {ps:.3g} kg m/s, "
                            f"angular {dL:.3g} of {Ls:.3g} kg m^2/s")
    if len(imp) == 0:
        note.append("no impact (the bodies missed each other)")
    return problems, pen, pen_tol, gain


MECHANICAL = ("Painleve",)
"""Words of a SimulationError message that name a real mechanical cause (a refusal)."""


def run_drop(dim, sseed, spec=None, bodies=1, planar=False, loop=None):
    """Build, run and check one scene (``bodies`` 1: a drop scene, ``draw_scene``, made
    planar with ``planar``; 2: a two-body scene, ``draw_pair_scene``); returns a
    ``DropRow``. ``loop``: the event loop it runs on, "scene" or "general"
    (``_setup.LOOP_KINDS``; the same results), None for ``$RBIMPACT_LOOP``'s."""
    import warnings
    two = bodies == 2
    draw, build, check = ((draw_pair_scene, build_pair_scene, check_pair_result) if two else
                          (draw_stack_scene, build_stack_scene, check_stack_result)
                          if bodies == STACK_BODIES else (None, build_scene, check_result))
    if spec is None:
        spec = draw(dim, sseed) if draw is not None else draw_scene(dim, sseed, planar)
    p = spec["params"]
    row = dict(dim=dim, seed=int(sseed), shape=spec["shape"], law=spec["law"],
               layout=spec["layout"], policy=spec["policy"], e=p["e"], mu=p["mu"],
               height=spec["height"], planar=bool(spec.get("planar", False)))
    t0 = time.perf_counter()
    note = []
    try:
        sim, t_end, max_events = build(spec)
    except Exception as exc:        # a scene the campaign draws must be accepted
        return DropRow(**row, verdict="FAIL", status="not built", impacts=0,
                       penetration=0.0, pen_tol=0.0, energy_gain=0.0,
                       wall=time.perf_counter() - t0,
                       note=f"scene not built: {type(exc).__name__}: {exc}"[:300])
    if loop is not None:
        from ._setup import check_loop
        sim.loop = check_loop("run_drop", loop)
    verdict, res = "OK", None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            res = sim.run(t_end, max_events=max_events)
        status = res.status
        if status != "done":
            verdict = "FAIL"
            note.append(f"status {status!r} after {len(res.events)} events at "
                        f"t = {res.t_end:.6g} s")
    except (NoSolutionError, SimulationError) as exc:
        res = getattr(exc, "result", None)
        msg = str(exc)
        mech = isinstance(exc, NoSolutionError) or any(m in msg for m in MECHANICAL)
        verdict = "REFUSED" if mech else "FAIL"
        status = type(exc).__name__
        note.append(msg[:300])
    except Exception as exc:
        verdict, status = "FAIL", type(exc).__name__
        note.append(f"{type(exc).__name__}: {exc}"[:300])
    wall = time.perf_counter() - t0
    try:
        problems, pen, pen_tol, gain = check(spec, sim, res, note)
    except Exception as exc:
        problems, pen, pen_tol, gain = [f"check failed: {type(exc).__name__}: {exc}"], 0, 0, 0
    if problems:
        verdict = "FAIL"
        note = problems + note
    n_imp = 0 if res is None else int(np.sum(res.events["kind"] == "impact"))
    return DropRow(**row, verdict=verdict, status=status, impacts=n_imp, penetration=pen,
                   pen_tol=pen_tol, energy_gain=gain, wall=wall, note="; ".join(note)[:400])


# ============================================================================================
# the campaign and its report
# ============================================================================================
@dataclass
class CampaignReport:
    """The rows of a campaign, with a table of counts and the failures' reproducers."""

    rows: list
    elapsed: float

    @property
    def ok(self):
        return not any(r.verdict == "FAIL" for r in self.rows)

    def counts(self, key):
        out = {}
        for r in self.rows:
            k = key(r)
            c = out.setdefault(k, {"OK": 0, "REFUSED": 0, "FAIL": 0})
            c[r.verdict] += 1
        return out

    def table(self):
        """Counts per dimension, shape and law; then one line per failure."""
        lines = []
        for title, key in (("dim shape", lambda r: (f"{r.dim}D", r.shape)),
                           ("dim law", lambda r: (f"{r.dim}D", r.law)),
                           ("dim layout policy", lambda r: (f"{r.dim}D", r.layout, r.policy))):
            c = self.counts(key)
            lines.append(f"{title:<34} {'scenes':>7} {'OK':>6} {'REFUSED':>8} {'FAIL':>6}")
            for k in sorted(c):
                v = c[k]
                lines.append(f"{' '.join(k):<34} {sum(v.values()):>7} {v['OK']:>6} "
                             f"{v['REFUSED']:>8} {v['FAIL']:>6}")
            lines.append("")
        fails = [r for r in self.rows if r.verdict != "OK"]
        for r in fails:
            lines.append(f"{r.verdict:<7} {r.reproducer}  [{r.shape} {r.law} e={r.e:g} "
                         f"mu={r.mu:g} {r.layout} {r.policy} h={r.height:.2g}] {r.note[:160]}")
        lines.append(self.summary())
        return "\n".join(lines)

    def summary(self):
        n = len(self.rows)
        c = {k: sum(r.verdict == k for r in self.rows) for k in ("OK", "REFUSED", "FAIL")}
        return (f"campaign: {n} scenes in {self.elapsed:.1f} s: {c['OK']} OK, {c['REFUSED']} "
                f"refused (mechanical), {c['FAIL']} FAIL -> {'ok' if self.ok else 'FAILED'}")

    def write_csv(self, path):
        import csv
        with open(path, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(list(DropRow.FIELDS) + ["reproducer"])
            for r in self.rows:
                w.writerow(r.fields())


def drop_campaign(n_scenes, dim="both", seed=0, progress=None, bodies=1, planar=False,
                  loop=None):
    """Run ``n_scenes`` random scenes per dimension (``dim``: 2, 3 or "both") from campaign
    seed ``seed``; returns a ``CampaignReport``. ``progress``: optional callable receiving
    each ``DropRow``. ``bodies``: 1 (the drop scenes), 2 (the two-body axis,
    ``draw_pair_scene``, its own seed stream ``pair_scene_seed``) or 3 (the stack axis, 2D,
    ``draw_stack_scene``, seed stream ``stack_scene_seed``). ``planar``: the planar
    axis, the 3D drop scenes of the same seeds made planar (``_make_planar``; 3D, one body).
    ``loop``: the event loop of every scene (``run_drop``)."""
    if bodies not in (1, 2, STACK_BODIES) or isinstance(bodies, bool):
        raise ValueError(f"drop_campaign: bodies must be 1, 2 or {STACK_BODIES}, got "
                         f"{bodies!r}")
    if bodies == STACK_BODIES:
        if dim not in (2, "2", "both"):
            raise ValueError(f"drop_campaign: the stack axis (bodies = {STACK_BODIES}) is 2D "
                             f"(dim 2), got dim = {dim!r}")
        dim = 2
    if planar and (bodies != 1 or dim not in (3, "3")):
        raise ValueError(f"drop_campaign: the planar axis is 3D drop scenes (dim 3, bodies 1), "
                         f"got dim = {dim!r}, bodies = {bodies!r}")
    if isinstance(n_scenes, bool) or not isinstance(n_scenes, (int, np.integer)) \
            or n_scenes < 1:
        raise ValueError(f"drop_campaign: n_scenes must be a positive integer, got "
                         f"{n_scenes!r}")
    from ._setup import check_loop
    check_loop("drop_campaign", loop)
    dims = {2: (2,), 3: (3,), "2": (2,), "3": (3,), "both": (2, 3)}.get(dim)
    if dims is None:
        raise ValueError(f"drop_campaign: dim must be 2, 3 or 'both', got {dim!r}")
    t0 = time.perf_counter()
    rows = []
    seeder = {2: pair_scene_seed, STACK_BODIES: stack_scene_seed}.get(bodies, scene_seed)
    for d in dims:
        for k in range(int(n_scenes)):
            rows.append(run_drop(d, seeder(d, seed, k), bodies=bodies, planar=planar,
                                 loop=loop))
            if progress:
                progress(rows[-1])
    return CampaignReport(rows, time.perf_counter() - t0)


def _progress_bar(total):
    """A progress callback: a tqdm bar on a terminal (``rbimpact.progress`` when present),
    nothing otherwise."""
    try:
        from .progress import progress
    except ImportError:
        return None, None
    bar = progress(None, total=total, desc="scenes")
    if bar is None or not hasattr(bar, "update"):
        return None, None
    return (lambda row: bar.update(1)), bar


def replay_text(dim, sseed, bodies=1, planar=False):
    """One scene, run again and explained: what was drawn, how it ended, the checks."""
    spec = (draw_pair_scene(dim, sseed) if bodies == 2 else draw_stack_scene(dim, sseed)
            if bodies == STACK_BODIES else draw_scene(dim, sseed, planar))
    row = run_drop(dim, sseed, spec, bodies=bodies)
    lines = [f"scene {dim}:{sseed}"]
    for k, v in spec.items():
        lines.append(f"  {k:<12} {v}")
    lines.append(f"  -> {row.verdict}: status {row.status}, {row.impacts} impacts, penetration "
                 f"{row.penetration:.3g} m (tol {row.pen_tol:.2g}), energy gain "
                 f"{row.energy_gain:.3g} of the scene's scale, {row.wall:.3f} s")
    if row.note:
        lines.append(f"  {row.note}")
    return "\n".join(lines), row


def main(args):
    """``rbimpact stability --scenes N [--dim 2|3|both] [--seed S] [--bodies 2|3] [--planar]
    [--out CSV]`` and ``--replay DIM:SEED``: print the table; exit status 1 when a scene
    FAILs."""
    if args.replay is not None:
        try:
            d, sd = args.replay.split(":")
            d, sd = int(d), int(sd)
            if d not in (2, 3) or sd < 0:
                raise ValueError
        except ValueError:
            raise ValueError(f"--replay takes DIM:SEED with DIM 2 or 3 and a seed >= 0 (as "
                             f"printed by a failure), got {args.replay!r}") from None
        text, row = replay_text(d, sd, getattr(args, "bodies", 1),
                                getattr(args, "planar", False))
        print(text)
        return 0 if row.verdict != "FAIL" else 1
    dims = 2 if args.dim == "both" and getattr(args, "bodies", 1) == 1 else 1
    cb, bar = _progress_bar(args.scenes * dims)
    try:
        report = drop_campaign(args.scenes, dim=args.dim, seed=args.seed, progress=cb,
                               bodies=getattr(args, "bodies", 1),
                               planar=getattr(args, "planar", False))
    finally:
        if bar is not None:
            bar.close()
    print(report.table())
    if args.out:
        report.write_csv(args.out)
    return 0 if report.ok else 1
