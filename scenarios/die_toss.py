"""die_toss: a cube thrown onto a table bounces, tumbles and comes to rest on a face; a
batch mode tosses it many times with random initial conditions and counts the faces."""
import math
import sys
import time
from dataclasses import dataclass

import numpy as np

from . import ALL_LAWS, Scenario, law_params, make_law, nonnegative, positive, register

DESCRIPTION = """\
A uniform cube (edge `size` m, mass `mass` kg: a die) is thrown from height `height` (m,
its centre) over a table (the plane z = 0) with speed `speed` (m/s) along +x (plus a
random sideways and vertical part of up to `speed`/4), a uniformly random orientation and
a random angular velocity of about `spin` rad/s (seeded by `seed`). It bounces on corners
and edges, tumbles over them (impacts that accumulate at a corner or an edge turn into an
integrated pivoting contact, with stick and slip), and comes to rest on a face: the run
ends with a "rest" event and one body axis exactly vertical. The cube's inertia is
spherical, so its flight is exact (closed form). Faces: +x = 1, +y = 2, +z = 3, -z = 4,
-y = 5, -x = 6 (opposite faces sum to 7); `die_toss_batch(n, seed)` counts the faces that
come up over n random tosses."""

#: face number of the body axis pointing up: (axis, sign) -> face
FACES = {(0, 1): 1, (1, 1): 2, (2, 1): 3, (2, -1): 4, (1, -1): 5, (0, -1): 6}
#: a toss has ended on a face when its up axis is within this of a body axis (rad)
FACE_TOL = 1e-6


@dataclass(frozen=True)
class Scenario3D(Scenario):
    """A ``Scenario`` whose scene is a ``Scene3D``: ``simulation()`` builds a
    ``Simulation3D`` (same keywords as ``Simulation``)."""

    def simulation(self, **tolerances):
        from rbimpact.simulation3d import Simulation3D
        kw = {**self.tolerances, **tolerances}
        return Simulation3D(self.scene, self.law, pair_laws=self.pair_laws, **kw)


def random_toss(seed, speed, spin, height):
    """(orientation, velocity, angular velocity) of toss ``seed``: orientation uniform on
    the rotations (a normalised Gaussian quaternion), velocity ``speed`` along +x plus
    uniform sideways and vertical parts in [-speed/4, speed/4] (m/s), angular velocity
    Gaussian with standard deviation ``spin/sqrt(3)`` per axis (rad/s)."""
    rng = np.random.default_rng(seed)
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    v = np.array([speed, 0.0, 0.0]) + rng.uniform(-0.25, 0.25, 3) * speed
    w = rng.normal(size=3) * spin / math.sqrt(3.0)
    return tuple(q), tuple(v), tuple(w)


@register("die_toss", laws=ALL_LAWS,
          summary="a die thrown onto a table tumbles and comes to rest on a face",
          help={"size": "edge of the cube (m), > 0",
                "mass": "mass of the cube (kg), > 0",
                "height": "initial height of its centre (m), > size * sqrt(3)/2",
                "speed": "throw speed (m/s), >= 0",
                "spin": "typical angular speed (rad/s), >= 0",
                "seed": "random seed of the initial orientation, velocity and spin",
                "g": "gravity (m/s^2), > 0",
                "t_end": "end time (s), > 0"})
def build(law: str = "chatterjee_ruina", e: float = 0.5, mu: float = 0.5, e_t: float = 0.0,
          restitution: str = "energetic", size: float = 0.016, mass: float = 0.0045,
          height: float = 0.15, speed: float = 1.0, spin: float = 30.0, seed: int = 0,
          g: float = 9.81, t_end: float = 3.0):
    """A die (``Box3D(size)``) thrown onto the table z = 0."""
    from rbimpact.scene3d import Scene3D
    from rbimpact.shapes3d import Box3D
    positive("die_toss", size=size, mass=mass, g=g, t_end=t_end)
    nonnegative("die_toss", speed=speed, spin=spin)
    if not height > size * math.sqrt(3.0) / 2.0:
        raise ValueError(f"scenario 'die_toss': height must be > size sqrt(3)/2 = "
                         f"{size * math.sqrt(3) / 2:g} m (the die must start above the "
                         f"table), got {height!r}")
    values = dict(law=law, e=e, mu=mu, e_t=e_t, restitution=restitution, size=size,
                  mass=mass, height=height, speed=speed, spin=spin, seed=seed, g=g,
                  t_end=t_end)
    the_law = make_law(law, **law_params(values))
    q, v, w = random_toss(seed, speed, spin, height)
    scene = Scene3D(gravity=(0.0, 0.0, -g))
    table = scene.add_floor(0.0)
    die = scene.add_body(Box3D(size), mass, (0.0, 0.0, height), orientation=q, velocity=v,
                         angular_velocity=w)
    return Scenario3D("die_toss", DESCRIPTION, scene, the_law, None, t_end, ALL_LAWS, values,
                      {}, None, max_events=200_000, bodies={"die": die},
                      planes={"table": table})


def face_up(result, body=0, tol=FACE_TOL):
    """The face (1..6) of ``body`` pointing up at the end of ``result``, or None when the
    body is not at rest with a body axis within ``tol`` (rad) of the vertical."""
    ev = result.events
    mine = ev[ev["a"] == body]
    if len(mine) == 0 or str(mine["kind"][-1]) != "rest":
        return None
    s = result.sample([result.t_end])
    q = s["orientation"][0, body]
    w_, x, y, z = q
    R = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w_ * z), 2 * (x * z + w_ * y)],
                  [2 * (x * y + w_ * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w_ * x)],
                  [2 * (x * z - w_ * y), 2 * (y * z + w_ * x), 1 - 2 * (x * x + y * y)]])
    up = R.T @ (-np.asarray(result.gravity) / np.linalg.norm(result.gravity))
    k = int(np.argmax(np.abs(up)))
    if math.acos(min(1.0, abs(float(up[k])))) > tol:
        return None
    return FACES[(k, 1 if up[k] > 0 else -1)]


def die_toss_batch(n, seed=0, law="chatterjee_ruina", progress=True, stream=None, **params):
    """Toss the die ``n`` times with random initial conditions (tosses ``seed``,
    ``seed + 1``, ...; other scenario parameters in ``params``) and count the faces that
    come up. Returns a dict face (1..6) -> count, plus "unresolved" (runs that ended in an
    error or not at rest on a face by ``t_end``), "impacts" (total), "seconds" (wall time)
    and "errors" (a list of (seed, message) for the unresolved runs). With ``progress``,
    prints a progress bar and the face frequencies to ``stream`` (default stderr)."""
    from rbimpact import scenarios
    from rbimpact.errors import NoSolutionError, SimulationError
    stream = sys.stderr if stream is None else stream
    if not (isinstance(n, (int, np.integer)) and n >= 1):
        raise ValueError(f"die_toss_batch: n must be a positive integer, got {n!r}")
    counts = {f: 0 for f in range(1, 7)}
    counts["unresolved"] = 0
    errors = []
    impacts = 0
    t0 = time.perf_counter()
    width = 40
    for k in range(n):
        sc = scenarios.get("die_toss", law=law, seed=int(seed) + k, **params)
        try:
            r = sc.simulate()
            f = face_up(r)
            impacts += r.n_impacts
        except (SimulationError, NoSolutionError) as exc:
            f = None
            errors.append((int(seed) + k, str(exc)))
        if f is None:
            counts["unresolved"] += 1
            if not errors or errors[-1][0] != int(seed) + k:
                errors.append((int(seed) + k, "not at rest on a face at t_end"))
        else:
            counts[f] += 1
        if progress and (k + 1 == n or (k + 1) % max(1, n // 200) == 0):
            done = (k + 1) / n
            el = time.perf_counter() - t0
            bar = "#" * int(width * done) + "-" * (width - int(width * done))
            stream.write(f"\rdie_toss {law}: [{bar}] {k + 1}/{n} "
                         f"{(k + 1) / el:.0f} tosses/s")
            stream.flush()
    counts["impacts"] = impacts
    counts["seconds"] = time.perf_counter() - t0
    counts["errors"] = errors
    if progress:
        stream.write("\n")
        resolved = n - counts["unresolved"]
        for f in range(1, 7):
            frac = counts[f] / resolved if resolved else 0.0
            stream.write(f"  face {f}: {counts[f]:6d}  {frac:6.1%}  {'#' * int(60 * frac)}\n")
        stream.write(f"  unresolved: {counts['unresolved']} of {n}; {impacts} impacts in "
                     f"{counts['seconds']:.2f} s ({n / counts['seconds']:.1f} tosses/s)\n")
        stream.flush()
    return counts
