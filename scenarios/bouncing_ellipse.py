"""bouncing_ellipse: a spinning ellipse bouncing on a rough floor."""
import math

from . import ALL_LAWS, FirstImpact, Scenario, law_params, make_law, positive, register

DESCRIPTION = """\
A uniform elliptical disk (semi-axes `a` along its own x axis and `b`, m; mass `mass` kg)
is released with its centre at height `height` (m), at angle `angle` (rad), spinning at
`omega` (rad/s), moving at `vx` (m/s), above a rough floor. The contact point runs round
the boundary as it turns, so each impact has a different lever arm and coupling: spin
and bounce exchange energy irregularly. Reference (omega = 0): the exact time of the
first impact.
The event-driven stepper has no persistent one-point (pivoting or rolling) contact:
run much longer than the default end time and the impacts accumulate at one point, which
ends the run with SimulationError; the default end time stays inside the bouncing phase."""


@register("bouncing_ellipse", laws=ALL_LAWS,
          summary="a spinning ellipse bouncing irregularly on a rough floor",
          help={"a": "semi-axis along the body's x axis (m), > 0",
                "b": "other semi-axis (m), > 0",
                "mass": "mass (kg), > 0",
                "height": "initial height of the centre (m)",
                "angle": "initial angle of the a axis from the horizontal (rad)",
                "omega": "initial angular velocity (rad/s, counter-clockwise)",
                "vx": "initial horizontal velocity (m/s)",
                "g": "gravity (m/s^2), > 0"})
def build(law: str = "routh", e: float = 0.8, mu: float = 0.3, e_t: float = 0.0,
          restitution: str = "energetic", a: float = 0.2, b: float = 0.1, mass: float = 1.0,
          height: float = 1.0, angle: float = 0.4, omega: float = 3.0, vx: float = 0.0,
          g: float = 9.81):
    """Ellipse centred at (0, ``height``) above a floor at y = 0."""
    from rbimpact import Ellipse, Scene2D
    positive("bouncing_ellipse", a=a, b=b, mass=mass, g=g)
    reach = math.sqrt((a * math.sin(angle)) ** 2 + (b * math.cos(angle)) ** 2)
    if not height - reach > 0:
        raise ValueError(f"scenario 'bouncing_ellipse': the ellipse must start above the "
                         f"floor: height must be > {reach:g} m at this angle, got {height!r}")
    values = dict(law=law, e=e, mu=mu, e_t=e_t, restitution=restitution, a=a, b=b, mass=mass,
                  height=height, angle=angle, omega=omega, vx=vx, g=g)
    the_law = make_law(law, **law_params(values))
    scene = Scene2D(gravity=(0.0, -g))
    floor = scene.add_floor(0.0)
    body = scene.add_body(Ellipse(a, b), mass, (0.0, height), angle=angle, velocity=(vx, 0.0),
                          angular_velocity=omega)
    ref = FirstImpact(height - reach, g) if omega == 0.0 else None
    return Scenario("bouncing_ellipse", DESCRIPTION, scene, the_law, None, 2.0, ALL_LAWS,
                    values, {}, ref, bodies={"ellipse": body}, planes={"floor": floor})
