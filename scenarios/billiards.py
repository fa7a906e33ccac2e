"""billiards: a cue ball breaking a small rack on a frictionless table (top view)."""
import math

from . import ALL_LAWS, Scenario, law_params, make_law, positive, register

DESCRIPTION = """\
Top view of a pool table (`width` x `depth` m, four cushions as half-planes, no gravity,
no friction): a cue ball (body 0) shot at `speed` (m/s), `aim` (rad) off the table's long
axis, into a triangle of `n_balls` object balls (radius `radius` m, mass `mass` kg) set
`gap` (m) apart so that no two touch at the start. Every impact is frictionless, so all
laws give Newton's restitution `e` and must agree; with e = 1 kinetic energy is conserved
exactly. Ball-ball impacts use restitution `e`, ball-cushion impacts `e_cushion` (a pair
law per cushion plane). The aim offset breaks the symmetry so that contacts are not
simultaneous."""


def rack(n, x0, y0, spacing):
    """Centres of ``n`` balls in a triangle, apex at (x0, y0), rows along +x."""
    out, row = [], 0
    while len(out) < n:
        for j in range(row + 1):
            if len(out) < n:
                out.append((x0 + row * spacing * math.sqrt(3.0) / 2.0,
                            y0 + (j - row / 2.0) * spacing))
        row += 1
    return out


@register("billiards", laws=ALL_LAWS,
          summary="a cue ball breaking a rack of balls between four cushions, frictionless",
          help={"e_cushion": "restitution of ball-cushion impacts (-), [0, 1]",
                "n_balls": "number of object balls in the rack, 1..15",
                "radius": "ball radius (m), > 0",
                "mass": "ball mass (kg), > 0",
                "width": "table length along x (m), > 0",
                "depth": "table width along y (m), > 0",
                "speed": "cue ball speed (m/s), > 0",
                "aim": "cue direction from the +x axis (rad)",
                "gap": "distance between neighbouring balls in the rack (m), > 0"})
def build(law: str = "routh", e: float = 0.95, e_cushion: float = 0.85, n_balls: int = 6,
          radius: float = 0.028575,
          mass: float = 0.17, width: float = 2.24, depth: float = 1.12, speed: float = 3.0,
          aim: float = 0.01, gap: float = 0.002):
    """Cue ball at (width/4, depth/2); rack apex at (0.7 width, depth/2)."""
    from rbimpact import Disk, Scene2D
    positive("billiards", radius=radius, mass=mass, width=width, depth=depth, speed=speed,
             gap=gap)
    if not 1 <= n_balls <= 15:
        raise ValueError(f"scenario 'billiards': n_balls must be in 1..15, got {n_balls}")
    values = dict(law=law, e=e, e_cushion=e_cushion, n_balls=n_balls, radius=radius,
                  mass=mass, width=width, depth=depth, speed=speed, aim=aim, gap=gap)
    the_law = make_law(law, **law_params(values))
    spacing = 2.0 * radius + gap
    centres = rack(n_balls, 0.7 * width, 0.5 * depth, spacing)
    xs = [c[0] for c in centres] + [0.25 * width]
    ys = [c[1] for c in centres] + [0.5 * depth]
    if (max(xs) + radius >= width or min(ys) - radius <= 0.0
            or max(ys) + radius >= depth or 0.25 * width - radius <= 0.0):
        raise ValueError("scenario 'billiards': the balls do not fit on the table; enlarge "
                         "width/depth or reduce n_balls/radius")
    scene = Scene2D(gravity=(0.0, 0.0))
    planes = {"left": scene.add_plane((0.0, 0.0), (1.0, 0.0)),
              "right": scene.add_plane((width, 0.0), (-1.0, 0.0)),
              "bottom": scene.add_plane((0.0, 0.0), (0.0, 1.0)),
              "top": scene.add_plane((0.0, depth), (0.0, -1.0))}
    bodies = {"cue": scene.add_body(Disk(radius), mass, (0.25 * width, 0.5 * depth),
                                    velocity=(speed * math.cos(aim), speed * math.sin(aim)))}
    for k, c in enumerate(centres):
        bodies[f"ball{k + 1}"] = scene.add_body(Disk(radius), mass, c)
    cushion = make_law(law, e=e_cushion)
    pair_laws = {plane: cushion for plane in planes.values()}
    return Scenario("billiards", DESCRIPTION, scene, the_law, pair_laws, 5.0, ALL_LAWS,
                    values, {}, None, bodies=bodies, planes=planes)
