"""dice_collide: two dice thrown at each other over a table collide in the air, land,
tumble and come to rest (3D body-body impacts, issue 16)."""
import math

from . import ALL_LAWS, law_params, make_law, nonnegative, positive, register
from .die_toss import FACES, Scenario3D, face_up, random_toss  # noqa: F401  (face_up re-exported)

DESCRIPTION = """\
Two uniform cubes (edge `size` m, mass `mass` kg: dice) start `separation` m apart along x
at height `height` (m, their centres) over a table (the plane z = 0) and are thrown at each
other with speed `speed` (m/s) along the line of their centres (plus the random sideways
and vertical parts of `die_toss`), with uniformly random orientations and random angular
velocities of about `spin` rad/s (seeded by `seed` and `seed + 1`). They meet in the air:
the time of impact of the two boxes by conservative advancement (kernels/pair3d_toi.py), the
contact points from the box-box manifold (a corner, an edge or a face: kernels/
pair3d_manifold.py), resolved by the law with W built from both bodies. Then each bounces,
tumbles over its corners and edges on the table (integrated pivoting contact) and comes to
rest on a face. While one die pivots on the table, the other is kept at a safe distance by
a bound on its reachable region (stepper3d._held_pair); dice that end up touching each
other stop with the named refusal of persistent body-body contact (issue 16). Faces as in
`die_toss`. Typical ranges: size 0.005-0.05 m, speed 0.2-3 m/s, separation 3-30 sizes."""


@register("dice_collide", laws=ALL_LAWS,
          summary="two dice thrown at each other collide in the air, land and come to rest",
          help={"size": "edge of each cube (m), > 0",
                "mass": "mass of each cube (kg), > 0",
                "height": "initial height of their centres (m), > size * sqrt(3)/2",
                "separation": "initial distance of their centres along x (m), > size * sqrt(3)",
                "speed": "throw speed of each die toward the other (m/s), >= 0",
                "spin": "typical angular speed (rad/s), >= 0",
                "seed": "random seed of the first die's orientation, velocity and spin "
                        "(the second uses seed + 1)",
                "g": "gravity (m/s^2), > 0",
                "t_end": "end time (s), > 0"})
def build(law: str = "chatterjee_ruina", e: float = 0.5, mu: float = 0.5, e_t: float = 0.0,
          restitution: str = "energetic", size: float = 0.016, mass: float = 0.0045,
          height: float = 0.1, separation: float = 0.12, speed: float = 1.0,
          spin: float = 10.0, seed: int = 0, g: float = 9.81, t_end: float = 2.0):
    """Two dice (``Box3D(size)``) at ``(-+separation / 2, 0, height)`` thrown at each other
    over the table z = 0."""
    from rbimpact.scene3d import Scene3D
    from rbimpact.shapes3d import Box3D
    positive("dice_collide", size=size, mass=mass, g=g, t_end=t_end)
    nonnegative("dice_collide", speed=speed, spin=spin)
    if not height > size * math.sqrt(3.0) / 2.0:
        raise ValueError(f"scenario 'dice_collide': height must be > size sqrt(3)/2 = "
                         f"{size * math.sqrt(3) / 2:g} m (the dice must start above the "
                         f"table), got {height!r}")
    if not separation > size * math.sqrt(3.0):
        raise ValueError(f"scenario 'dice_collide': separation must be > size sqrt(3) = "
                         f"{size * math.sqrt(3):g} m (the dice must start apart), got "
                         f"{separation!r}")
    values = dict(law=law, e=e, mu=mu, e_t=e_t, restitution=restitution, size=size,
                  mass=mass, height=height, separation=separation, speed=speed, spin=spin,
                  seed=seed, g=g, t_end=t_end)
    the_law = make_law(law, **law_params(values))
    scene = Scene3D(gravity=(0.0, 0.0, -g))
    table = scene.add_floor(0.0)
    dice = []
    for k, sign in enumerate((1.0, -1.0)):
        q, v, w = random_toss(int(seed) + k, speed, spin, height)
        v = (sign * v[0], v[1], v[2])
        dice.append(scene.add_body(Box3D(size), mass, (-0.5 * sign * separation, 0.0, height),
                                   orientation=q, velocity=v, angular_velocity=w))
    return Scenario3D("dice_collide", DESCRIPTION, scene, the_law, None, t_end, ALL_LAWS,
                      values, {}, None, max_events=200_000,
                      bodies={"left": dice[0], "right": dice[1]}, planes={"table": table})
