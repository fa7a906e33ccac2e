"""bouncing_ball: a disk dropped onto a floor; exact impact times (DESIGN §5)."""
import math
from dataclasses import dataclass

import numpy as np

from . import ALL_LAWS, Scenario, law_params, make_law, positive, register

DESCRIPTION = """\
A disk of radius `radius` (m) is dropped from rest (horizontal speed `vx`) with its lowest
point at height `h` (m) above a floor, under gravity `g` (m/s^2). With restitution e < 1
it bounces at t_1 = sqrt(2h/g), t_{k+1} = t_k + 2 e^k sqrt(2gh)/g, infinitely often
before t_inf = t_1 (1+e)/(1-e); the stepper must jump to t_inf and leave the ball at rest
(or sliding, then rolling if mu > 0, when vx != 0). The floor normal does not couple to rotation, so every law
gives these normal velocities and the reference holds for any law and any mu.
`elastic=true` sets e = 1, mu = 0 (energy conserved, no accumulation: a benchmark).
End time: t_inf + 1 s (10 s when e >= 0.95). Brach with e < 0 sends the ball through the
floor (no reference then)."""


@dataclass(frozen=True)
class BouncingBallReference:
    """Exact impact times of a ball dropped from rest from height ``h`` (m, lowest point
    above the floor) with restitution ``e`` under gravity ``g`` (m/s^2), DESIGN §5."""

    h: float
    e: float
    g: float

    @property
    def v0(self):
        """Impact speed of the first impact (m/s)."""
        return math.sqrt(2.0 * self.g * self.h)

    @property
    def t1(self):
        """Time of the first impact (s)."""
        return math.sqrt(2.0 * self.h / self.g)

    @property
    def t_inf(self):
        """Accumulation time of the impacts (s); inf for e = 1, t1 for e = 0."""
        return math.inf if self.e >= 1.0 else self.t1 * (1.0 + self.e) / (1.0 - self.e)

    def impact_times(self, n):
        """The first ``n`` impact times t_1..t_n (s), float64 array."""
        # flight k (between impacts k and k + 1, k >= 1) lasts 2 e^k v0 / g
        flights = 2.0 * self.e ** np.arange(1, max(n, 1)) * self.v0 / self.g
        t = np.empty(n)
        if n:
            t[0] = self.t1
            t[1:] = self.t1 + np.cumsum(flights)
        return t

    def impact_speeds(self, n):
        """Normal speed just before each of the first ``n`` impacts (m/s)."""
        return self.v0 * self.e ** np.arange(n)

    def __call__(self, n=30):
        return self.impact_times(n)


@register("bouncing_ball", laws=ALL_LAWS,
          summary="a disk dropped on a floor, bouncing until it rests at t_inf (exact)",
          help={"h": "drop height of the disk's lowest point above the floor (m), > 0",
                "radius": "disk radius (m), > 0",
                "mass": "disk mass (kg), > 0",
                "g": "gravity (m/s^2), > 0",
                "vx": "initial horizontal velocity (m/s)",
                "elastic": "e = 1, mu = 0: no accumulation, energy conserved (benchmark)"})
def build(law: str = "routh", e: float = 0.8, mu: float = 0.0, e_t: float = 0.0,
          restitution: str = "energetic", h: float = 1.0, radius: float = 0.05,
          mass: float = 1.0, g: float = 9.80665, vx: float = 0.0, elastic: bool = False):
    """Disk of ``radius`` (m), ``mass`` (kg) with its lowest point ``h`` (m) above a floor
    at y = 0, released at rest (plus ``vx``, m/s) under gravity ``g`` (m/s^2)."""
    from rbimpact import Disk, Scene2D
    positive("bouncing_ball", h=h, radius=radius, mass=mass, g=g)
    if elastic:
        e, mu = 1.0, 0.0
    values = dict(law=law, e=e, mu=mu, e_t=e_t, restitution=restitution, h=h, radius=radius,
                  mass=mass, g=g, vx=vx, elastic=elastic)
    the_law = make_law(law, **law_params(values))
    scene = Scene2D(gravity=(0.0, -g))
    floor = scene.add_floor(0.0)
    ball = scene.add_body(Disk(radius), mass, (0.0, h + radius), velocity=(vx, 0.0))
    ref = BouncingBallReference(h, e, g)
    if e < 0.0:   # Brach's perforation: the ball goes through the floor; no reference
        ref, t_end = None, 2.0 * ref.t1
    else:
        t_end = 10.0 if elastic or e >= 0.95 else ref.t_inf + 1.0
    return Scenario("bouncing_ball", DESCRIPTION, scene, the_law, None, t_end, ALL_LAWS,
                    values, {}, ref, bodies={"ball": ball}, planes={"floor": floor})
