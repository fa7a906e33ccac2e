"""perforation: Brach's law with e < 0, a body passing through a thin barrier."""
import math

from . import Scenario, law_params, make_law, nonnegative, positive, register

LAWS = ("brach",)

DESCRIPTION = """\
A small disk (radius `radius` m, mass `mass` kg, spin `omega` rad/s) is shot from the
origin at `speed` (m/s), `angle` (rad) from the +x axis, at a thin barrier: the vertical
line x = `barrier` (m). Brach's law with negative restitution e < 0 keeps the sign of the
normal velocity: the body goes through, its normal speed reduced to |e| times its value,
friction (mu, e_t) slowing the tangential motion. The barrier is modelled as the
half-plane x <= barrier with normal (-1, 0) (pointing back at the shooter): the perforating
impact happens where the disk's surface reaches the line, and the body then carries on
inside the half-plane (the gap stays negative, so no further impact is sought). Only
Brach's law admits e < 0. Gravity `g` (m/s^2) is 0 by default (a fast projectile)."""


@register("perforation", laws=LAWS,
          summary="Brach with e < 0: a disk shot through a thin barrier, slowed",
          help={"radius": "disk radius (m), > 0",
                "mass": "disk mass (kg), > 0",
                "speed": "initial speed (m/s), > 0",
                "angle": "direction of the shot from +x (rad), |angle| < pi/2",
                "omega": "initial spin (rad/s, counter-clockwise)",
                "barrier": "x position of the barrier (m), > radius",
                "g": "gravity (m/s^2), >= 0"})
def build(law: str = "brach", e: float = -0.5, mu: float = 0.2, e_t: float = 0.0,
          radius: float = 0.01, mass: float = 0.01, speed: float = 20.0, angle: float = 0.3,
          omega: float = 0.0, barrier: float = 1.0, g: float = 0.0):
    """Disk at the origin shot toward the barrier x = ``barrier`` (normal -x)."""
    from rbimpact import Disk, Scene2D
    positive("perforation", radius=radius, mass=mass, speed=speed)
    nonnegative("perforation", g=g)
    if not abs(angle) < 0.5 * math.pi:
        raise ValueError(f"scenario 'perforation': |angle| must be < pi/2 (toward the "
                         f"barrier), got {angle!r}")
    if not barrier > radius:
        raise ValueError(f"scenario 'perforation': barrier must be > radius = {radius:g} m, "
                         f"got {barrier!r}")
    values = dict(law=law, e=e, mu=mu, e_t=e_t, radius=radius, mass=mass, speed=speed,
                  angle=angle, omega=omega, barrier=barrier, g=g)
    the_law = make_law(law, **law_params(values))
    scene = Scene2D(gravity=(0.0, -g))
    wall = scene.add_plane((barrier, 0.0), (-1.0, 0.0))
    body = scene.add_body(Disk(radius), mass, (0.0, 0.0),
                          velocity=(speed * math.cos(angle), speed * math.sin(angle)),
                          angular_velocity=omega)
    t_hit = (barrier - radius) / (speed * math.cos(angle))
    return Scenario("perforation", DESCRIPTION, scene, the_law, None, 4.0 * t_hit, LAWS,
                    values, {}, None, bodies={"body": body}, planes={"barrier": wall})
