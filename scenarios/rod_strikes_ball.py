"""rod_strikes_ball: a spinning rod in flight strikes a ball (2D body-body impact, issue 16)."""
from . import ALL_LAWS, Scenario, law_params, make_law, nonnegative, positive, register

DESCRIPTION = """\
A uniform rod (length `length` m, mass `rod_mass` kg; a capsule when `radius` > 0),
centred `distance` m to the left of a ball (a disk of radius `ball_radius` m, mass
`ball_mass` kg), is thrown at it with speed `speed` m/s along +x while spinning at `omega`
rad/s; the ball's centre sits `offset` m above the line of the rod's centre. Both fall
freely under gravity `g` (no floor: the impacts happen in flight, and relative to each
other the bodies move as without gravity). The rod's end or side strikes the ball: the
impact couples the normal and tangential impulses through the rod's rotation (W_NT != 0),
where the laws differ; a fast spin can strike the ball more than once. Time of impact by
conservative advancement on the rod-disk pair (kernels/pair2d_toi.py), contact frame from
kernels/pair2d.py. Typical ranges: length 0.1-2 m, ball_radius 0.02-0.5 m, speed 0.5-20
m/s, omega -100-100 rad/s, |offset| below length / 2 + ball_radius (else no impact)."""


@register("rod_strikes_ball", laws=ALL_LAWS,
          summary="a spinning rod in flight strikes a ball (body-body impact)",
          help={"length": "rod length (m), > 0",
                "radius": "rod (capsule) radius (m), >= 0 (0: a segment)",
                "rod_mass": "rod mass (kg), > 0",
                "ball_radius": "ball radius (m), > 0",
                "ball_mass": "ball mass (kg), > 0",
                "distance": "initial distance of the centres along x (m), > 0; the bodies "
                            "must start apart",
                "speed": "rod speed toward the ball (m/s)",
                "omega": "rod angular velocity (rad/s, counter-clockwise)",
                "angle": "initial angle of the rod from the x axis (rad)",
                "offset": "height of the ball's centre above the rod's line of flight (m)",
                "g": "gravity (m/s^2), >= 0"})
def build(law: str = "routh", e: float = 0.8, mu: float = 0.3, e_t: float = 0.0,
          restitution: str = "energetic", length: float = 1.0, radius: float = 0.0,
          rod_mass: float = 1.0, ball_radius: float = 0.1, ball_mass: float = 0.5,
          distance: float = 1.5, speed: float = 3.0, omega: float = 6.0,
          angle: float = 1.2, offset: float = 0.2, g: float = 9.81):
    """Rod centred at (0, 10) (m), the ball at (``distance``, 10 + ``offset``)."""
    from rbimpact import Disk, Rod, Scene2D
    positive("rod_strikes_ball", length=length, rod_mass=rod_mass, ball_radius=ball_radius,
             ball_mass=ball_mass, distance=distance)
    nonnegative("rod_strikes_ball", radius=radius, g=g)
    reach = 0.5 * length + radius + ball_radius
    if not distance > reach:
        raise ValueError(f"scenario 'rod_strikes_ball': the rod and the ball must start "
                         f"apart: distance {distance:g} m must exceed length / 2 + radius + "
                         f"ball_radius = {reach:g} m")
    values = dict(law=law, e=e, mu=mu, e_t=e_t, restitution=restitution, length=length,
                  radius=radius, rod_mass=rod_mass, ball_radius=ball_radius,
                  ball_mass=ball_mass, distance=distance, speed=speed, omega=omega,
                  angle=angle, offset=offset, g=g)
    the_law = make_law(law, **law_params(values))
    scene = Scene2D(gravity=(0.0, -g))
    y0 = 10.0
    rod = scene.add_body(Rod(length, radius=radius), rod_mass, (0.0, y0), angle=angle,
                         velocity=(speed, 0.0), angular_velocity=omega)
    ball = scene.add_body(Disk(ball_radius), ball_mass, (distance, y0 + offset))
    # long enough for the rod to cross the ball's place twice over at its speed
    t_end = 2.0 * (distance + reach) / max(abs(speed), 1e-3)
    return Scenario("rod_strikes_ball", DESCRIPTION, scene, the_law, None, min(t_end, 1.0),
                    ALL_LAWS, values, {}, None, bodies={"rod": rod, "ball": ball})
