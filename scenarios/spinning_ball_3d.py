"""spinning_ball_3d: a ball with topspin and sidespin bouncing on a rough floor: its
bounce direction curves."""
import numpy as np

from . import ALL_LAWS, law_params, make_law, positive, register
from .die_toss import Scenario3D

DESCRIPTION = """\
A solid ball (radius `radius` m, mass `mass` kg) is thrown along +x at `vx` (m/s) from
lowest-point height `h` (m) over a rough floor, spinning with `topspin` (rad/s, about +y:
forward roll) and `sidespin` (rad/s, about +x, the direction of travel: a tilted spin
axis). At each bounce friction acts on the slip of the contact point, which the sidespin
points sideways (-y for positive sidespin): every bounce kicks the ball sideways and turns
some spin into velocity, so with little friction (mu = 0.05) the bounce direction turns
from bounce to bounce while the contact point slips (the first bounces: the bounce
points curve away from the x axis), until the ball's spin matches its motion and it
bounces on in a straight line. (Spin about the vertical axis alone would not:
a point contact exerts no torque about the normal.) The bounces then accumulate, the ball
slides and finally rolls in a straight line. Reference: `reference.turn(result)` gives
the heading (degrees) of the horizontal velocity after every impact."""


class SpinReference:
    """Headings of the horizontal velocity after each impact (degrees from +x)."""

    @staticmethod
    def turn(result):
        imp = result.events[result.events["kind"] == "impact"]
        s = result.sample(imp["t"])
        v = s["velocity"][:, 0, :]
        return np.degrees(np.arctan2(v[:, 1], v[:, 0]))


@register("spinning_ball_3d", laws=ALL_LAWS,
          summary="a ball with topspin and sidespin: its bounce direction curves",
          help={"h": "drop height of the ball's lowest point (m), > 0",
                "radius": "ball radius (m), > 0",
                "mass": "ball mass (kg), > 0",
                "vx": "initial forward velocity (m/s)",
                "topspin": "spin about +y (rad/s): forward roll",
                "sidespin": "spin about +x, the direction of travel (rad/s)",
                "g": "gravity (m/s^2), > 0",
                "t_end": "end time (s), > 0"})
def build(law: str = "routh", e: float = 0.8, mu: float = 0.05, e_t: float = 0.0,
          restitution: str = "energetic", h: float = 1.0, radius: float = 0.1,
          mass: float = 1.0, vx: float = 2.0, topspin: float = 20.0, sidespin: float = 40.0,
          g: float = 9.81, t_end: float = 4.0):
    """Ball thrown along +x from x = 0 with topspin and sidespin."""
    from rbimpact.scene3d import Scene3D
    from rbimpact.shapes3d import Sphere
    positive("spinning_ball_3d", h=h, radius=radius, mass=mass, g=g, t_end=t_end)
    values = dict(law=law, e=e, mu=mu, e_t=e_t, restitution=restitution, h=h, radius=radius,
                  mass=mass, vx=vx, topspin=topspin, sidespin=sidespin, g=g, t_end=t_end)
    the_law = make_law(law, **law_params(values))
    scene = Scene3D(gravity=(0.0, 0.0, -g))
    floor = scene.add_floor(0.0)
    ball = scene.add_body(Sphere(radius), mass, (0.0, 0.0, h + radius), velocity=(vx, 0, 0),
                          angular_velocity=(sidespin, topspin, 0.0))
    return Scenario3D("spinning_ball_3d", DESCRIPTION, scene, the_law, None, t_end, ALL_LAWS,
                      values, {}, SpinReference(), bodies={"ball": ball},
                      planes={"floor": floor})
