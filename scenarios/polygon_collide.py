"""polygon_collide: two or three convex polygons thrown together in flight (2D, issue 16)."""
import math

from . import ALL_LAWS, Scenario, law_params, make_law, nonnegative, positive, register

DESCRIPTION = """\
`count` regular convex polygons (2 or 3; `sides` corners each, circumradius `size` m,
mass `mass` kg) start on a circle of radius `spread` m around the origin, evenly spaced,
each turned by its own angle, spinning at `omega` rad/s (alternating sign), and are thrown
toward the origin at `speed` m/s, aimed `miss` m to the side of it (so that they meet
off-centre). No gravity by default (`g` m/s^2 pulls along -y; there is no floor: the
impacts happen in flight). Corner-on-edge impacts couple normal and tangential impulses
through the rotation; edges meeting flat make clusters of two contacts (the policy
applies). Typical ranges: size 0.05-1 m, spread 2-10 times size, speed 0.5-20 m/s,
|omega| below 100 rad/s, |miss| below size."""


@register("polygon_collide", laws=ALL_LAWS,
          summary="two or three convex polygons colliding in flight",
          help={"count": "number of polygons, 2 or 3",
                "sides": "corners of each polygon, 3 to 12",
                "size": "circumradius of each polygon (m), > 0",
                "mass": "mass of each polygon (kg), > 0",
                "spread": "initial distance of each centre from the origin (m); the "
                          "polygons must start apart",
                "speed": "speed toward the origin (m/s)",
                "omega": "spin (rad/s), alternating sign from one polygon to the next",
                "miss": "aim this far to the side of the origin (m)",
                "g": "gravity (m/s^2, along -y), >= 0"})
def build(law: str = "routh", e: float = 0.8, mu: float = 0.3, e_t: float = 0.0,
          restitution: str = "energetic", count: int = 3, sides: int = 5, size: float = 0.2,
          mass: float = 1.0, spread: float = 1.0, speed: float = 2.0, omega: float = 4.0,
          miss: float = 0.05, g: float = 0.0):
    """Polygons on a circle of radius ``spread`` thrown at the origin."""
    from rbimpact import Polygon, Scene2D
    if count not in (2, 3):
        raise ValueError(f"scenario 'polygon_collide': count must be 2 or 3, got {count!r}")
    if not 3 <= sides <= 12:
        raise ValueError(f"scenario 'polygon_collide': sides must be 3 to 12, got {sides!r}")
    positive("polygon_collide", size=size, mass=mass, spread=spread)
    nonnegative("polygon_collide", g=g)
    gap = 2.0 * spread * math.sin(math.pi / count) - 2.0 * size
    if not gap > 0.0:
        raise ValueError(f"scenario 'polygon_collide': the polygons must start apart: "
                         f"spread {spread:g} m is too small for size {size:g} m (their "
                         f"circumcircles overlap by {-gap:g} m)")
    values = dict(law=law, e=e, mu=mu, e_t=e_t, restitution=restitution, count=count,
                  sides=sides, size=size, mass=mass, spread=spread, speed=speed,
                  omega=omega, miss=miss, g=g)
    the_law = make_law(law, **law_params(values))
    shape = Polygon([(size * math.cos(2 * math.pi * k / sides),
                      size * math.sin(2 * math.pi * k / sides)) for k in range(sides)])
    scene = Scene2D(gravity=(0.0, -g))
    bodies = {}
    for i in range(count):
        a = 2 * math.pi * i / count
        ux, uy = math.cos(a), math.sin(a)
        vx = -speed * ux - speed * (miss / spread) * uy
        vy = -speed * uy + speed * (miss / spread) * ux
        bodies[f"polygon{i}"] = scene.add_body(
            shape, mass, (spread * ux, spread * uy), angle=0.37 * (i + 1),
            velocity=(vx, vy), angular_velocity=omega * (1 if i % 2 == 0 else -1))
    t_end = min(2.0 * spread / max(abs(speed), 1e-3), 2.0)
    return Scenario("polygon_collide", DESCRIPTION, scene, the_law, None, t_end, ALL_LAWS,
                    values, {}, None, bodies=bodies)
