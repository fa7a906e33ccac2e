"""superball: Garwin's superball bouncing between a floor and the underside of a table."""
from . import ALL_LAWS, Scenario, law_params, make_law, positive, register

DESCRIPTION = """\
Garwin's superball (Am. J. Phys. 37:88, 1969): a small rough, elastic ball (radius
`radius` m, mass `mass` kg, uniform disk) is thrown from (0, `y0`) with velocity
(`vx`, `vy`) m/s and spin `omega` (rad/s) under a table: it bounces on the floor (y = 0),
then on the table's underside (a half-plane at y = `table` m with downward normal), then
on the floor again. With Chatterjee & Ruina's law and tangential restitution e_t near 1
(the contact point's tangential velocity reverses) the table bounce reverses the
horizontal velocity: the ball comes back out toward the thrower. Brach's law with the
same e_t does the same inside its friction cone. Kane & Levinson and Routh (at best the
contact point sticks) do not bring it back; Smith's law, which never sticks and with
large mu reverses the slip (final slip -> minus the initial one), does. The ball is a
uniform disk (I = m r^2 / 2), not Garwin's sphere, so the numbers differ from his."""


@register("superball", laws=ALL_LAWS,
          summary="Garwin's superball under a table: e_t near 1 makes it come back",
          help={"radius": "ball radius (m), > 0",
                "mass": "ball mass (kg), > 0",
                "table": "height of the table's underside (m), > y0 + radius",
                "y0": "initial height of the ball's centre (m), > radius",
                "vx": "initial horizontal velocity, toward under the table (m/s)",
                "vy": "initial vertical velocity (m/s)",
                "omega": "initial spin (rad/s, counter-clockwise)",
                "g": "gravity (m/s^2), > 0"})
def build(law: str = "chatterjee_ruina", e: float = 0.9, mu: float = 1.0, e_t: float = 0.95,
          restitution: str = "energetic", radius: float = 0.025, mass: float = 0.05,
          table: float = 0.8, y0: float = 0.4, vx: float = 2.0, vy: float = -4.0,
          omega: float = 0.0, g: float = 9.81):
    """Ball between a floor (y = 0) and a table underside (y = ``table``, normal -y)."""
    from rbimpact import Disk, Scene2D
    positive("superball", radius=radius, mass=mass, g=g)
    if not radius < y0 < table - radius:
        raise ValueError(f"scenario 'superball': need radius < y0 < table - radius, got "
                         f"radius={radius!r}, y0={y0!r}, table={table!r}")
    values = dict(law=law, e=e, mu=mu, e_t=e_t, restitution=restitution, radius=radius,
                  mass=mass, table=table, y0=y0, vx=vx, vy=vy, omega=omega, g=g)
    the_law = make_law(law, **law_params(values))
    scene = Scene2D(gravity=(0.0, -g))
    floor = scene.add_floor(0.0)
    underside = scene.add_plane((0.0, table), (0.0, -1.0))
    ball = scene.add_body(Disk(radius), mass, (0.0, y0), velocity=(vx, vy),
                          angular_velocity=omega)
    return Scenario("superball", DESCRIPTION, scene, the_law, None, 1.0, ALL_LAWS, values,
                    {}, None, bodies={"ball": ball},
                    planes={"floor": floor, "table": underside})
