"""rocking_block: a block dropped tilted, rocking from corner to corner."""
import math

from . import ALL_LAWS, FirstImpact, Scenario, law_params, make_law, positive, register

DESCRIPTION = """\
A uniform block (`width` x `height` m, mass `mass` kg) is dropped tilted by `angle` (rad)
with its lowest corner `drop` (m) above a rough floor (spin `omega` rad/s). It lands on
that corner, which rotates it onto the other corner, and so on: it rocks from corner to
corner (Housner's rocking block, resolved here as a sequence of corner impacts, with
restitution high enough that each corner leaves the floor again). With `angle` below
atan(width/height) it does not topple. Reference (omega = 0): the first impact time.
Run longer and the impacts accumulate at one corner: the block then pivots on it (an
integrated persistent contact, as a rocking block with plastic corner impacts really
moves), lands on the other corner, and comes to rest on its base."""


@register("rocking_block", laws=ALL_LAWS,
          summary="a block dropped tilted, rocking from corner to corner",
          help={"width": "box width (m), > 0",
                "height": "box height (m), > 0",
                "mass": "box mass (kg), > 0",
                "angle": "initial tilt (rad, counter-clockwise)",
                "drop": "initial height of the lowest corner above the floor (m), > 0",
                "omega": "initial angular velocity (rad/s, counter-clockwise)",
                "g": "gravity (m/s^2), > 0"})
def build(law: str = "routh", e: float = 0.9, mu: float = 1.0, e_t: float = 0.0,
          restitution: str = "energetic", width: float = 0.4, height: float = 0.4,
          mass: float = 1.0, angle: float = 0.2, drop: float = 0.01, omega: float = 0.0,
          g: float = 9.81):
    """Box tilted by ``angle`` with its lowest corner ``drop`` (m) above a floor at y = 0."""
    from rbimpact import Box, Scene2D
    positive("rocking_block", width=width, height=height, mass=mass, g=g, drop=drop)
    values = dict(law=law, e=e, mu=mu, e_t=e_t, restitution=restitution, width=width,
                  height=height, mass=mass, angle=angle, drop=drop, omega=omega, g=g)
    the_law = make_law(law, **law_params(values))
    reach = 0.5 * width * abs(math.sin(angle)) + 0.5 * height * abs(math.cos(angle))
    scene = Scene2D(gravity=(0.0, -g))
    floor = scene.add_floor(0.0)
    box = scene.add_body(Box(width, height), mass, (0.0, drop + reach), angle=angle,
                         angular_velocity=omega)
    ref = FirstImpact(drop, g) if omega == 0.0 else None
    return Scenario("rocking_block", DESCRIPTION, scene, the_law, None, 1.0, ALL_LAWS, values,
                    {}, ref, bodies={"block": box}, planes={"floor": floor})
