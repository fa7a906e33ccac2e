"""box_stack: a stack of boxes resting on the floor (2D persistent body-body contact,
issue 16)."""
from . import ALL_LAWS, Scenario, law_params, make_law, nonnegative, positive, register

DESCRIPTION = """\
`count` equal boxes (`width` x `height` m, `mass` kg each) placed on a rough floor and on
each other, touching and at rest, each shifted `offset` m to the right of the one below
(|offset| below width / 2: every box's centre above the one below it). Their first
contacts accumulate at once: the stack enters one cluster (every face on a face held at the
two ends of the overlap, 2 count contacts) and comes to rest (frozen) when its contacts
can hold it (a static equilibrium with every friction force inside its cone); it then
stays for as long as it is run, with no drift. With the defaults (five boxes, Kane &
Levinson's law, e = 0, mu = 0.5) no box moves by more than 1e-15 m in 10 s. Limits: at
most 6 boxes (12 contacts, `cluster2d.KMAX`); beyond 6 contacts the modes are found by a
local search (`cluster2d.DSEL_MAX`). Typical ranges: sizes 0.05-1 m, masses 0.1-10 kg, mu
0.2-1."""


@register("box_stack", laws=ALL_LAWS,
          summary="a stack of boxes at rest on the floor (persistent body-body contact)",
          help={"count": "number of boxes, 1 to 6",
                "width": "box width (m), > 0",
                "height": "box height (m), > 0",
                "mass": "box mass (kg), > 0",
                "offset": "horizontal shift of each box from the one below (m), "
                          "|offset| < width / 2",
                "g": "gravity (m/s^2), > 0",
                "t_end": "duration (s), > 0"})
def build(law: str = "kane_levinson", e: float = 0.0, mu: float = 0.5, e_t: float = 0.0,
          restitution: str = "energetic", count: int = 5, width: float = 0.4,
          height: float = 0.2, mass: float = 1.0, offset: float = 0.02, g: float = 9.81,
          t_end: float = 10.0):
    """Boxes centred at x = k offset, y = (k + 1/2) height, k = 0 .. count - 1."""
    from rbimpact import Box, Scene2D
    positive("box_stack", width=width, height=height, mass=mass, g=g, t_end=t_end)
    nonnegative("box_stack", mu=mu)
    if count != int(count) or not 1 <= count <= 6:
        raise ValueError(f"scenario 'box_stack': count must be an integer from 1 to 6, "
                         f"got {count!r}")
    if not abs(offset) < width / 2:
        raise ValueError(f"scenario 'box_stack': |offset| must be below width / 2 = "
                         f"{width / 2!r}, got {offset!r}")
    count = int(count)
    values = dict(law=law, e=e, mu=mu, e_t=e_t, restitution=restitution, count=count,
                  width=width, height=height, mass=mass, offset=offset, g=g, t_end=t_end)
    the_law = make_law(law, **law_params(values))
    scene = Scene2D(gravity=(0.0, -g))
    floor = scene.add_floor(0.0)
    bodies = {}
    for k in range(count):
        bodies[f"box{k}"] = scene.add_body(Box(width, height), mass,
                                           (k * offset, (k + 0.5) * height))
    return Scenario("box_stack", DESCRIPTION, scene, the_law, None, t_end, ALL_LAWS,
                    values, {}, None, bodies=bodies, planes={"floor": floor})
