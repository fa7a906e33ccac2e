"""falling_rod: a tilted rod dropped on a rough floor, bouncing on alternate ends."""
import math

from . import ALL_LAWS, FirstImpact, Scenario, law_params, make_law, nonnegative, positive, \
    register

DESCRIPTION = """\
A uniform rod (length `length` m, mass `mass` kg; a capsule when `radius` > 0) is
released with its centre at height `height` (m), tilted by `angle` (rad) from the
horizontal, with spin `omega` (rad/s) and horizontal velocity `vx` (m/s), above a rough
floor. Each impact on one end throws the other end down: the rod clatters on alternate
ends, many times. The lower end's impact couples normal and tangential
impulses (W_NT != 0), which is where the laws differ (and where Kane & Levinson may create
energy). Reference (omega = 0): the exact time of the first impact.
Run longer and the impacts accumulate at one end: the rod then pivots (or slides) on it
in integrated persistent contact, slams down on the other end, and comes to rest."""


@register("falling_rod", laws=ALL_LAWS,
          summary="a tilted rod clattering on a rough floor on alternate ends",
          help={"length": "rod length (m), > 0",
                "radius": "capsule radius (m), >= 0 (0: a segment)",
                "mass": "rod mass (kg), > 0",
                "height": "initial height of the centre (m)",
                "angle": "initial tilt from the horizontal (rad)",
                "omega": "initial angular velocity (rad/s, counter-clockwise)",
                "vx": "initial horizontal velocity (m/s)",
                "g": "gravity (m/s^2), > 0"})
def build(law: str = "routh", e: float = 0.8, mu: float = 0.3, e_t: float = 0.0,
          restitution: str = "energetic", length: float = 1.0, radius: float = 0.0,
          mass: float = 1.0, height: float = 1.0, angle: float = 0.5, omega: float = 0.0,
          vx: float = 0.0, g: float = 9.81):
    """Rod centred at (0, ``height``) tilted by ``angle`` above a floor at y = 0."""
    from rbimpact import Rod, Scene2D
    positive("falling_rod", length=length, mass=mass, g=g)
    nonnegative("falling_rod", radius=radius)
    gap = height - 0.5 * length * abs(math.sin(angle)) - radius
    if not gap > 0:
        raise ValueError(f"scenario 'falling_rod': the rod must start above the floor; its "
                         f"lowest point is at {gap:g} m (raise height)")
    values = dict(law=law, e=e, mu=mu, e_t=e_t, restitution=restitution, length=length,
                  radius=radius, mass=mass, height=height, angle=angle, omega=omega, vx=vx,
                  g=g)
    the_law = make_law(law, **law_params(values))
    scene = Scene2D(gravity=(0.0, -g))
    floor = scene.add_floor(0.0)
    rod = scene.add_body(Rod(length, radius=radius), mass, (0.0, height), angle=angle,
                         velocity=(vx, 0.0), angular_velocity=omega)
    ref = FirstImpact(gap, g) if omega == 0.0 else None
    return Scenario("falling_rod", DESCRIPTION, scene, the_law, None, 2.0, ALL_LAWS, values,
                    {}, ref, bodies={"rod": rod}, planes={"floor": floor})
