"""superball_3d: Garwin's superball bouncing between a floor and the underside of a table,
in 3D."""
from . import ALL_LAWS, law_params, make_law, positive, register
from .die_toss import Scenario3D

DESCRIPTION = """\
Garwin's superball (Am. J. Phys. 37:88, 1969) in 3D: a small rough elastic ball (radius
`radius` m, mass `mass` kg, solid) is thrown from (0, 0, `z0`) with velocity (`vx`, `vy`,
`vz`) m/s and spin (`wx`, `wy`, `wz`) rad/s under a table whose underside is the plane
z = `table` (normal -z): it bounces on the floor, on the underside, on the floor again.
With Chatterjee & Ruina's law and tangential restitution e_t near 1 the contact point's
tangential velocity reverses at each bounce, so after the floor-table-floor sequence the
whole horizontal velocity (both components) comes back: the ball returns toward the
thrower, in 3D as in 2D. Laws without e_t (Kane & Levinson, Smith, Routh) do not bring it
back."""


@register("superball_3d", laws=ALL_LAWS,
          summary="Garwin's superball under a table, in 3D: e_t near 1 makes it come back",
          help={"radius": "ball radius (m), > 0",
                "mass": "ball mass (kg), > 0",
                "table": "height of the table's underside (m), > z0 + radius",
                "z0": "initial height of the ball's centre (m), > radius",
                "vx": "initial velocity toward under the table (m/s)",
                "vy": "initial sideways velocity (m/s)",
                "vz": "initial vertical velocity (m/s)",
                "wx": "initial spin about x (rad/s)",
                "wy": "initial spin about y (rad/s)",
                "wz": "initial spin about z (rad/s)",
                "g": "gravity (m/s^2), > 0",
                "t_end": "end time (s), > 0"})
def build(law: str = "chatterjee_ruina", e: float = 0.9, mu: float = 1.0, e_t: float = 0.95,
          restitution: str = "energetic", radius: float = 0.025, mass: float = 0.05,
          table: float = 0.8, z0: float = 0.4, vx: float = 2.0, vy: float = 0.7,
          vz: float = -4.0, wx: float = 0.0, wy: float = 0.0, wz: float = 0.0,
          g: float = 9.81, t_end: float = 1.0):
    """Ball between a floor (z = 0) and a table underside (z = ``table``, normal -z)."""
    from rbimpact.scene3d import Scene3D
    from rbimpact.shapes3d import Sphere
    positive("superball_3d", radius=radius, mass=mass, g=g, t_end=t_end)
    if not radius < z0 < table - radius:
        raise ValueError(f"scenario 'superball_3d': need radius < z0 < table - radius, got "
                         f"radius={radius!r}, z0={z0!r}, table={table!r}")
    values = dict(law=law, e=e, mu=mu, e_t=e_t, restitution=restitution, radius=radius,
                  mass=mass, table=table, z0=z0, vx=vx, vy=vy, vz=vz, wx=wx, wy=wy, wz=wz,
                  g=g, t_end=t_end)
    the_law = make_law(law, **law_params(values))
    scene = Scene3D(gravity=(0.0, 0.0, -g))
    floor = scene.add_floor(0.0)
    underside = scene.add_plane((0.0, 0.0, table), (0.0, 0.0, -1.0))
    ball = scene.add_body(Sphere(radius), mass, (0.0, 0.0, z0), velocity=(vx, vy, vz),
                          angular_velocity=(wx, wy, wz))
    return Scenario3D("superball_3d", DESCRIPTION, scene, the_law, None, t_end, ALL_LAWS,
                      values, {}, None, bodies={"ball": ball},
                      planes={"floor": floor, "table": underside})
