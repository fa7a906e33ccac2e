"""polygon_gas: a gas of N random convex polygons (or a mix of polygons, disks and
capsules) in a box of four walls, run by the exact 2D stepper (``rbimpact.Simulation``,
every body pair collides with exact time of impact; issue 16)."""
import math

import numpy as np

from . import ALL_LAWS, Scenario, law_params, make_law, nonnegative, positive, register

SHAPES = ("polygons", "mixed", "disks")
#: random sequential insertion gives up after this many tries per body
PLACE_TRIES = 10_000

DESCRIPTION = """\
A gas of `n` bodies in the square box [0, L] x [0, L] closed by four walls (planes), no
gravity by default. `shapes=polygons`: random convex polygons, 3 to `max_sides` corners
each (a regular polygon of circumradius `size` m with its corner angles jittered and
stretched by a random factor 0.6-1 along a random direction, so every one differs);
`shapes=mixed`: polygons, disks (radius `size`) and capsules (length 1.2 `size`, radius
0.4 `size`) in turn; `shapes=disks`: disks of radius `size` (the same gas through the
same stepper, for comparison). Every body has mass `mass` kg and the uniform-density
moment of inertia of its shape; the bodies sit at random non-overlapping places (their
circumcircles apart), at random angles, with Maxwellian velocities and spins of
temperature `temperature` (J: <m v_x^2> = <I w^2> = T), total momentum removed. L is
chosen so that the shapes cover the fraction `packing` of the box. Every impact, body on
body (any pair of shapes, exact time of impact) or body on wall, uses the law; with
e = 1, mu = 0 (Kane & Levinson, the default) kinetic energy is conserved to round-off.
The run lasts `crossings` times the time L / v_rms. Persistent body-body contact is not
built: a dissipative gas that clusters ends with status 'persistent_pair'. Typical
ranges: n 2-200, packing 0.05-0.3, size 0.01-1 m."""


def random_polygon(rng, sides, size):
    """Vertices (sides, 2) of a random convex polygon of circumradius at most ``size`` (m):
    the corners of a regular polygon, each angle jittered by up to a third of the corner
    spacing (so the corners stay in order on the circle: convex), then the outline
    stretched by a factor 0.6-1 along a random direction (an affine map keeps it convex)."""
    k = np.arange(sides)
    ang = 2.0 * math.pi * (k + rng.uniform(-1.0 / 3.0, 1.0 / 3.0, sides)) / sides
    p = size * np.column_stack([np.cos(ang), np.sin(ang)])
    phi = rng.uniform(0.0, math.pi)
    u = np.array([math.cos(phi), math.sin(phi)])
    s = rng.uniform(0.6, 1.0)
    return p + (s - 1.0) * np.outer(p @ u, u)


def make_shapes(n, shapes, size, max_sides, rng):
    """The ``n`` shapes of the gas (``SHAPES``)."""
    from rbimpact import Disk, Polygon, Rod
    out = []
    for i in range(n):
        kind = shapes if shapes != "mixed" else ("polygons", "disks", "capsules")[i % 3]
        if kind == "polygons":
            out.append(Polygon(random_polygon(rng, int(rng.integers(3, max_sides + 1)), size)))
        elif kind == "disks":
            out.append(Disk(size))
        else:
            out.append(Rod(1.2 * size, radius=0.4 * size))
    return out


@register("polygon_gas", laws=ALL_LAWS,
          summary="a gas of random convex polygons (or polygons, disks, capsules) in a box",
          help={"n": "number of bodies, >= 1",
                "shapes": "polygons, mixed (polygons, disks, capsules in turn) or disks",
                "max_sides": "most corners of a polygon, 3 to 12",
                "size": "circumradius of a polygon, radius of a disk (m), > 0",
                "mass": "mass of every body (kg), > 0",
                "packing": "fraction of the box the shapes cover, in (0, 0.35]",
                "temperature": "k_B T (J): <m v_x^2> = <I w^2> = T, > 0",
                "crossings": "run time in units of L / v_rms (box side over rms speed), > 0",
                "g": "gravity (m/s^2, along -y), >= 0",
                "seed": "random seed of shapes, places and velocities"},
          choices={"shapes": SHAPES})
def build(law: str = "kane_levinson", e: float = 1.0, mu: float = 0.0, e_t: float = 0.0,
          restitution: str = "energetic", n: int = 16, shapes: str = "polygons",
          max_sides: int = 7, size: float = 0.1, mass: float = 1.0, packing: float = 0.15,
          temperature: float = 1.0, crossings: float = 5.0, g: float = 0.0, seed: int = 0):
    """The gas; ``Scenario.simulate()`` runs it with ``rbimpact.Simulation``."""
    from rbimpact import Scene2D
    if n < 1:
        raise ValueError(f"scenario 'polygon_gas': n must be >= 1, got {n!r}")
    if not 3 <= max_sides <= 12:
        raise ValueError(f"scenario 'polygon_gas': max_sides must be 3 to 12, got "
                         f"{max_sides!r}")
    positive("polygon_gas", size=size, mass=mass, packing=packing, temperature=temperature,
             crossings=crossings)
    nonnegative("polygon_gas", g=g)
    if packing > 0.35:
        raise ValueError(f"scenario 'polygon_gas': packing must be <= 0.35 (random insertion "
                         f"of the circumcircles), got {packing!r}")
    rng = np.random.default_rng(seed)
    shp = make_shapes(n, shapes, size, max_sides, rng)
    area = sum(s.area for s in shp)
    L = math.sqrt(area / packing)
    rad = np.array([s.bounding_radius for s in shp])
    if L <= 2.0 * rad.max():
        L = 2.0 * rad.max() * 1.01
    pos = np.zeros((n, 2))
    for i in range(n):
        for _ in range(PLACE_TRIES):
            p = rng.uniform(rad[i], L - rad[i], 2)
            if i == 0 or np.all(np.hypot(*(pos[:i] - p).T) > rad[:i] + rad[i]):
                pos[i] = p
                break
        else:
            raise ValueError(f"scenario 'polygon_gas': could not place body {i} of {n} "
                             f"after {PLACE_TRIES} tries: lower packing")
    sd = math.sqrt(temperature / mass)
    vel = rng.normal(0.0, sd, (n, 2))
    if n > 1:
        vel -= vel.mean(axis=0)
    moments = np.array([s.moment(mass) for s in shp])
    omega = rng.normal(0.0, 1.0, n) * np.sqrt(temperature / moments)
    angles = rng.uniform(0.0, 2.0 * math.pi, n)
    values = dict(law=law, e=e, mu=mu, e_t=e_t, restitution=restitution, n=n, shapes=shapes,
                  max_sides=max_sides, size=size, mass=mass, packing=packing,
                  temperature=temperature, crossings=crossings, g=g, seed=seed)
    the_law = make_law(law, **law_params(values))
    scene = Scene2D(gravity=(0.0, -g))
    bodies = {}
    for i in range(n):
        bodies[f"body{i}"] = scene.add_body(
            shp[i], mass, (float(pos[i, 0]), float(pos[i, 1])), angle=float(angles[i]),
            velocity=(float(vel[i, 0]), float(vel[i, 1])), angular_velocity=float(omega[i]))
    planes = {"left": scene.add_plane((0.0, 0.0), (1.0, 0.0)),
              "right": scene.add_plane((L, 0.0), (-1.0, 0.0)),
              "bottom": scene.add_plane((0.0, 0.0), (0.0, 1.0)),
              "top": scene.add_plane((0.0, L), (0.0, -1.0))}
    vrms = math.sqrt(2.0 * temperature / mass)
    t_end = crossings * L / vrms
    return Scenario("polygon_gas", DESCRIPTION, scene, the_law, None, t_end, ALL_LAWS, values,
                    {}, None, bodies=bodies, planes=planes)
