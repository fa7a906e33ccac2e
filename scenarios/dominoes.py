"""dominoes: a row of dominoes toppling one another on a rough floor (2D persistent
body-body contact, issue 16)."""
import math

import numpy as np

from . import ALL_LAWS, Scenario, law_params, make_law, nonnegative, positive, register

DESCRIPTION = """\
`count` equal dominoes (`width` x `height` m, `mass` kg) stand on a rough floor, their
centres `spacing` m apart. The first is tilted forward by `tilt` rad on its front bottom
corner (beyond the tipping angle atan(width / height) it falls by itself) and turned at
`push` rad/s. Each falling domino strikes the next near its top, leans on it, and the
chain of leaning dominoes falls as one cluster of persistent contacts (cluster2d: corners
sliding or sticking on faces and on the floor) until the last lies on the floor and the
others rest on one another. The run reports which dominoes toppled, the times the front
reached each one and its speed (spacing over the time between hits). The first strike's
time is the closed form of a box pivoting on a corner (`first_hit_time`). Limits: 2 to 8
dominoes (a cluster holds at most `cluster2d.KMAX` = 24 contacts); tested with Kane &
Levinson's law, e = 0, mu 0.3-0.8. Typical sizes: width 5-10 mm, height 40-50 mm,
spacing between width and height + width."""

MAX_COUNT = 8


def first_hit_time(width, height, spacing, tilt, g):
    """Time (s) at which the first domino, released from rest tilted by ``tilt`` rad on
    its front bottom corner (pivoting there without slip), strikes the next one with its
    front top corner: ``theta`` from ``tilt`` to ``asin((spacing - width) / height)``, with
    ``(1/2) I_c theta'^2 = m g r (cos b0 - cos b)``, ``b = theta - atan(width / height)``
    the angle of the corner-to-centre line from the vertical, ``r`` its length and ``I_c =
    m (width^2 + height^2) / 3`` (corner moment of a uniform box). The time integral
    ``int d(theta) / theta'`` is taken in ``u = sqrt(cos b0 - cos b)`` (smooth at the
    start, where theta' = 0): ``t = int 2 du / (sqrt(k) sin b(u))``, ``k = 2 m g r / I_c``.
    None when the first domino does not fall forward from rest (``tilt`` at or below the
    tipping angle)."""
    from scipy.integrate import quad
    phi = math.atan2(width, height)
    b0 = tilt - phi
    if not b0 > 0.0:
        return None
    r = 0.5 * math.hypot(width, height)
    k = 2.0 * g * r / ((width * width + height * height) / 3.0)
    b1 = math.asin((spacing - width) / height) - phi
    u1 = math.sqrt(math.cos(b0) - math.cos(b1))

    def f(u):
        return 2.0 / (math.sqrt(k) * math.sin(math.acos(math.cos(b0) - u * u)))
    t, _ = quad(f, 0.0, u1, epsabs=0.0, epsrel=1e-13, limit=200)
    return t


class DominoFront:
    """The chain's front: which dominoes toppled, when each was first struck, its speed."""

    def __init__(self, count, width, height, spacing, tilt, push, g):
        self.count = count
        self.width = width
        self.height = height
        self.spacing = spacing
        self.tilt_critical = math.atan2(width, height)
        self.t1 = first_hit_time(width, height, spacing, tilt, g) if push == 0.0 else None

    def hits(self, events):
        """Time (s) of the first impact of domino k - 1 on domino k, k = 1 .. count - 1
        (nan: never struck)."""
        out = np.full(self.count - 1, np.nan)
        imp = events[events["kind"] == "impact"]
        for k in range(1, self.count):
            m = ((imp["a"] == k - 1) & (imp["b"] == k)) | ((imp["a"] == k) & (imp["b"] == k - 1))
            if m.any():
                out[k - 1] = float(imp["t"][m][0])
        return out

    def toppled(self, result):
        """Per domino: True if it lies past its tipping angle at the run's end."""
        ang = np.asarray(result.sample([result.t_end])["angle"]).ravel()
        return np.abs(ang) > self.tilt_critical

    def speeds(self, events):
        """Front speed between successive hits (m/s): spacing / (t_k+1 - t_k)."""
        return self.spacing / np.diff(self.hits(events))

    def report_result(self, result):
        ev = result.events
        hits = self.hits(ev)
        down = self.toppled(result)
        lines = [f"dominoes: {int(down.sum())} of {self.count} toppled"
                 + (" (the chain completed)" if down.all() else "")]
        if np.isfinite(hits).any():
            lines.append("front: struck at t = " + ", ".join(
                f"{t:.6g}" if np.isfinite(t) else "-" for t in hits) + " s")
        v = self.speeds(ev)
        if np.isfinite(v).any():
            lines.append("front speed (m/s) between successive hits: " + ", ".join(
                f"{s:.4g}" for s in v[np.isfinite(v)]))
        if self.t1 is not None and np.isfinite(hits[0]):
            lines.append(f"reference: first strike at t = {self.t1:.12g} s (a box pivoting "
                         f"on a corner), relative error {abs(hits[0] - self.t1) / self.t1:.1e}")
        return lines


@register("dominoes", laws=ALL_LAWS,
          summary="a row of dominoes toppling one another (persistent body-body contact)",
          help={"count": f"number of dominoes, 2 to {MAX_COUNT}",
                "width": "domino thickness along the row (m), > 0",
                "height": "domino height (m), > width",
                "mass": "domino mass (kg), > 0",
                "spacing": "distance between neighbouring centres (m), in (width, height + "
                           "width): they stand apart, and a falling one reaches the next",
                "tilt": "forward tilt of the first domino on its front bottom corner (rad), "
                        "in [0, pi/2)",
                "push": "initial forward (clockwise) angular velocity of the first domino "
                        "(rad/s), >= 0",
                "g": "gravity (m/s^2), > 0",
                "t_end": "duration (s), > 0"})
def build(law: str = "kane_levinson", e: float = 0.0, mu: float = 0.5, e_t: float = 0.0,
          restitution: str = "energetic", count: int = 5, width: float = 0.01,
          height: float = 0.05, mass: float = 0.01, spacing: float = 0.03,
          tilt: float = 0.25, push: float = 0.0, g: float = 9.81, t_end: float = 2.0):
    """Domino k centred at x = k spacing (k >= 1), standing; the first turned by ``tilt``
    about its front bottom corner at x = width / 2."""
    from rbimpact import Box, Scene2D
    positive("dominoes", width=width, height=height, mass=mass, spacing=spacing, g=g,
             t_end=t_end)
    nonnegative("dominoes", mu=mu, tilt=tilt, push=push)
    if count != int(count) or not 2 <= count <= MAX_COUNT:
        raise ValueError(f"scenario 'dominoes': count must be an integer from 2 to "
                         f"{MAX_COUNT}, got {count!r}")
    if not height > width:
        raise ValueError(f"scenario 'dominoes': height must exceed width (a domino stands "
                         f"on its narrow face), got width {width!r} m, height {height!r} m")
    if not width < spacing < height + width:
        raise ValueError(f"scenario 'dominoes': spacing must lie in (width, height + width) = "
                         f"({width!r}, {height + width!r}) m (apart, and within reach of a "
                         f"falling domino), got {spacing!r}")
    if not tilt < 0.5 * math.pi:
        raise ValueError(f"scenario 'dominoes': tilt must be below pi/2 rad, got {tilt!r}")
    count = int(count)
    values = dict(law=law, e=e, mu=mu, e_t=e_t, restitution=restitution, count=count,
                  width=width, height=height, mass=mass, spacing=spacing, tilt=tilt,
                  push=push, g=g, t_end=t_end)
    the_law = make_law(law, **law_params(values))
    scene = Scene2D(gravity=(0.0, -g))
    floor = scene.add_floor(0.0)
    # the first: its front bottom corner (w/2, -h/2) in the body frame at (w/2, 0), turned
    # clockwise by tilt (angle -tilt)
    c, s = math.cos(tilt), math.sin(tilt)
    x0 = 0.5 * width - (0.5 * width * c - 0.5 * height * s)
    y0 = 0.5 * width * s + 0.5 * height * c
    bodies = {"domino0": scene.add_body(Box(width, height), mass, (x0, y0), angle=-tilt,
                                        angular_velocity=-push)}
    for k in range(1, count):
        bodies[f"domino{k}"] = scene.add_body(Box(width, height), mass,
                                              (k * spacing, 0.5 * height))
    ref = DominoFront(count, width, height, spacing, tilt, push, g)
    return Scenario("dominoes", DESCRIPTION, scene, the_law, None, t_end, ALL_LAWS, values,
                    {}, ref, bodies=bodies, planes={"floor": floor})
