"""spinning_ball: topspin and backspin balls onto a rough floor."""
from . import ALL_LAWS, Scenario, law_params, make_law, nonnegative, positive, register

DESCRIPTION = """\
Two equal disks (radius `radius` m, mass `mass` kg, uniform) are dropped with their
lowest points at height `h` (m) over a rough floor, both moving forward (+x) at `vx`
(m/s), `separation` (m) apart so that they never meet. Ball "topspin" (body 0, ahead)
spins forward, omega = -spin (rad/s, clockwise); ball "backspin" (body 1, behind) spins
backward, omega = +spin. At the first impact friction turns spin into horizontal speed:
the topspin ball leaps forward faster, the backspin ball bounces backward (-x) when
spin * radius is large enough against vx. Later bounces shrink until the balls roll."""


@register("spinning_ball", laws=ALL_LAWS,
          summary="topspin and backspin balls on a rough floor: forward and backward bounces",
          help={"h": "drop height of the balls' lowest points (m), > 0",
                "radius": "ball radius (m), > 0",
                "mass": "ball mass (kg), > 0",
                "vx": "initial forward velocity of both balls (m/s)",
                "spin": "spin rate (rad/s), >= 0: topspin -spin, backspin +spin",
                "separation": "initial horizontal distance between the balls (m), > 2 radius",
                "g": "gravity (m/s^2), > 0"})
def build(law: str = "routh", e: float = 0.7, mu: float = 0.4, e_t: float = 0.0,
          restitution: str = "energetic", h: float = 1.0, radius: float = 0.1,
          mass: float = 1.0, vx: float = 1.0, spin: float = 60.0, separation: float = 2.0,
          g: float = 9.81):
    """Topspin ball (body 0) at x = separation/2 and backspin ball (body 1) at
    x = -separation/2, both dropped from lowest-point height ``h`` (m)."""
    from rbimpact import Disk, Scene2D
    positive("spinning_ball", h=h, radius=radius, mass=mass, g=g)
    nonnegative("spinning_ball", spin=spin)
    if not separation > 2.0 * radius:
        raise ValueError(f"scenario 'spinning_ball': separation must be > 2 radius "
                         f"= {2 * radius:g} m, got {separation!r}")
    values = dict(law=law, e=e, mu=mu, e_t=e_t, restitution=restitution, h=h, radius=radius,
                  mass=mass, vx=vx, spin=spin, separation=separation, g=g)
    the_law = make_law(law, **law_params(values))
    scene = Scene2D(gravity=(0.0, -g))
    floor = scene.add_floor(0.0)
    y0 = h + radius
    top = scene.add_body(Disk(radius), mass, (0.5 * separation, y0), velocity=(vx, 0.0),
                         angular_velocity=-spin)
    back = scene.add_body(Disk(radius), mass, (-0.5 * separation, y0), velocity=(vx, 0.0),
                          angular_velocity=spin)
    return Scenario("spinning_ball", DESCRIPTION, scene, the_law, None, 3.0, ALL_LAWS, values,
                    {}, None, bodies={"topspin": top, "backspin": back},
                    planes={"floor": floor})
