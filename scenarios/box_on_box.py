"""box_on_box: a spinning box dropped onto a box that rocks on the floor (2D, issue 16)."""
import math

from . import ALL_LAWS, Scenario, law_params, make_law, nonnegative, positive, register

DESCRIPTION = """\
A base box (`width` x `height` m, mass `mass` kg), tilted by `angle` rad and spinning at
`omega` rad/s, is dropped with its lowest corner `drop` m above a rough floor; a smaller
top box (`top_width` x `top_height` m, mass `top_mass` kg), tilted by `top_angle` rad and
spinning at `top_omega` rad/s, is dropped from rest (centre `top_offset` m to the right
of the base's centre) with its lowest point `top_gap` m above the base's highest point.
The base lands on a corner and rocks from corner to corner on the floor while the top box
lands on it corner first and bounces on it: box-floor corner impacts and box-box
corner-on-face impacts alternate, each a single contact at its own instant. With the
defaults and Kane & Levinson's law (the one `rbimpact crosscheck box_on_box` uses) the
first eight impact instants are at least 20 ms apart, three of them box-box, and the top
box does not touch the floor before t_end. Run longer and the base's corner impacts
accumulate (it would pivot on a corner, or come to rest, with the top box on it):
persistent body-body contact is not built, so the run would stop with status
"persistent_pair"; with the defaults that happens after 1 s for every law (the earliest,
Routh's, at 1.03 s), and t_end is 0.8 s. Typical ranges: sizes 0.1-1 m, |angle| below
0.5 rad, drop 0.02-0.5 m, |omega| below 10 rad/s, |top_offset| below width / 2."""


def _reach(width, height, angle):
    """Half the vertical extent (m) of a width x height box turned by ``angle``."""
    return 0.5 * width * abs(math.sin(angle)) + 0.5 * height * abs(math.cos(angle))


@register("box_on_box", laws=ALL_LAWS,
          summary="a spinning box dropped onto a box rocking on the floor (box-box and "
                  "box-floor impacts)",
          help={"width": "base box width (m), > 0",
                "height": "base box height (m), > 0",
                "mass": "base box mass (kg), > 0",
                "angle": "base box initial tilt (rad, counter-clockwise)",
                "drop": "initial height of the base's lowest corner above the floor (m), > 0",
                "omega": "base box angular velocity (rad/s, counter-clockwise)",
                "top_width": "top box width (m), > 0",
                "top_height": "top box height (m), > 0",
                "top_mass": "top box mass (kg), > 0",
                "top_angle": "top box initial tilt (rad, counter-clockwise)",
                "top_gap": "initial height of the top box's lowest point above the base's "
                           "highest point (m), > 0",
                "top_offset": "horizontal position of the top box's centre from the "
                              "base's (m)",
                "top_omega": "top box angular velocity (rad/s, counter-clockwise)",
                "g": "gravity (m/s^2), > 0"})
def build(law: str = "routh", e: float = 0.8, mu: float = 0.3, e_t: float = 0.0,
          restitution: str = "energetic", width: float = 0.6, height: float = 0.3,
          mass: float = 2.0, angle: float = 0.2, drop: float = 0.17, omega: float = -2.0,
          top_width: float = 0.3, top_height: float = 0.2, top_mass: float = 1.0,
          top_angle: float = 0.75, top_gap: float = 0.23, top_offset: float = -0.1,
          top_omega: float = 4.0, g: float = 9.81):
    """Base box above a floor at y = 0, centred at x = 0; the top box above it."""
    from rbimpact import Box, Scene2D
    positive("box_on_box", width=width, height=height, mass=mass, drop=drop,
             top_width=top_width, top_height=top_height, top_mass=top_mass,
             top_gap=top_gap, g=g)
    nonnegative("box_on_box", mu=mu)
    values = dict(law=law, e=e, mu=mu, e_t=e_t, restitution=restitution, width=width,
                  height=height, mass=mass, angle=angle, drop=drop, omega=omega,
                  top_width=top_width, top_height=top_height, top_mass=top_mass,
                  top_angle=top_angle, top_gap=top_gap, top_offset=top_offset,
                  top_omega=top_omega, g=g)
    the_law = make_law(law, **law_params(values))
    scene = Scene2D(gravity=(0.0, -g))
    floor = scene.add_floor(0.0)
    reach = _reach(width, height, angle)
    y_base = drop + reach
    base = scene.add_body(Box(width, height), mass, (0.0, y_base), angle=angle,
                          angular_velocity=omega)
    y_top = y_base + reach + top_gap + _reach(top_width, top_height, top_angle)
    top = scene.add_body(Box(top_width, top_height), top_mass, (top_offset, y_top),
                         angle=top_angle, angular_velocity=top_omega)
    return Scenario("box_on_box", DESCRIPTION, scene, the_law, None, 0.8, ALL_LAWS,
                    values, {}, None, bodies={"base": base, "top": top},
                    planes={"floor": floor})
