"""painleve_rod: the classical Painleve rod, sliding on its lower end, against mu_P(theta)."""
import math

from . import ALL_LAWS, Scenario, law_params, make_law, nonnegative, positive, register

DESCRIPTION = """\
A uniform rod (length `length` m, mass `mass` kg, I = m l^2 / 3 with l = length / 2) stands
on a rough floor on its lower end, tilted by `angle` (rad) from the horizontal, and slides
at `vx` (m/s; negative: the lower end leads, moving away from the centre's side). Under a
normal force lam the end's normal acceleration is b + (W_NN - mu s W_NT) lam with
W_NN = (1 + 3 cos^2) / m and |W_NT| = 3 sin cos / m: sliding with the lower end leading
has no consistent contact force once mu > mu_P(angle) = (1 + 3 cos^2) / (3 sin cos)
(Painleve 1895; the minimum 4/3 at tan(angle) = 2). With painleve="impact" (default) the
jam is an impact without collision: Darboux-Keller's integration in the normal impulse
from v_N = 0 (Genot & Brogliato 1999), event "painleve"; with "error" the run stops with
status "painleve". Reference: mu_P(angle) and the closed-form impulse of the jam."""


def mu_p(angle):
    """Painleve's threshold of the uniform rod at tilt ``angle`` (rad), lower end leading."""
    c, s = math.cos(angle), math.sin(angle)
    return (1.0 + 3.0 * c * c) / (3.0 * abs(s * c))


def jam_impulse(angle, mu, vT, e, half, mass, radius=0.0):
    """Closed-form impact without collision of the rod's lower end (v_N = 0, slip ``vT``
    m/s, Poisson's ``e``; half-length ``half`` m, mass kg, I = m half^2 / 3; ``radius``: a
    capsule's, the contact point that much below the end): slide along ``-mu s`` until the
    slip stops, then stick (when ``|W_TN| <= mu W_TT``) until v_N is back at 0 (``p_c``);
    ``P_N = (1 + e) p_c``. Returns ``(P_N, P_T)`` (N s; t = +x, n = +y) or None when the
    slide is consistent (no jam)."""
    m, inertia = mass, mass * half ** 2 / 3.0
    rx, ry = -half * math.cos(angle), -half * math.sin(angle) - radius
    cn, ct = rx, ry                       # r x n and r x t for n = +y, t = +x
    wnn, wnt, wtt = 1 / m + cn * cn / inertia, -cn * ct / inertia, 1 / m + ct * ct / inertia
    s = math.copysign(1.0, vT)
    kN = wnn - mu * s * wnt
    kT = wnt - mu * s * wtt
    if not kN < 0.0 or not s * kT < 0.0 or not abs(wnt) <= mu * wtt:
        return None
    p1 = -vT / kT                         # the slip stops
    pc = p1 - kN * p1 * wtt / (wnn * wtt - wnt * wnt)    # v_N back at 0 while sticking
    pf = (1.0 + e) * pc
    return pf, -mu * s * p1 - wnt / wtt * (pf - p1)


class PainleveReference:
    """mu_P(angle) and the closed-form jam impulse (``jam_impulse``) of a ``painleve_rod``."""

    def __init__(self, angle, mu, vx, e, half, mass):
        self.mu_p = mu_p(angle)
        self.impulse = jam_impulse(angle, mu, vx, e, half, mass) if vx < 0.0 else None

    def report(self, events):
        """Lines comparing a run's first "painleve" event with the closed form."""
        line = f"reference: Painleve threshold mu_P = {self.mu_p:.6g}"
        jams = events[events["kind"] == "painleve"]
        if self.impulse is None:
            return [line + "; no jam expected (mu below it, or the end trails)"
                    + (f", but {len(jams)} happened" if len(jams) else "")]
        if not len(jams):
            return [line + "; a jam was expected at t = 0, none happened"]
        PN, PT = self.impulse
        err = max(abs(jams[0]["P"][0] - PN), abs(jams[0]["P"][1] - PT)) / PN
        return [line + f"; jam impulse (P_N, P_T) = ({PN:.9g}, {PT:.9g}) N s, "
                       f"relative error {err:.1e}"]


@register("painleve_rod", laws=ALL_LAWS,
          summary="the Painleve rod sliding on its leading end: jam above mu_P(angle)",
          help={"length": "rod length (m), > 0",
                "mass": "rod mass (kg), > 0",
                "angle": "tilt from the horizontal (rad), in (0, pi/2)",
                "vx": "sliding velocity (m/s); < 0: the lower end leads",
                "g": "gravity (m/s^2), >= 0",
                "painleve": "impact (a jam is an impact without collision) or error"},
          choices={"painleve": ("impact", "error")})
def build(law: str = "kane_levinson", e: float = 0.0, mu: float = 4.0, e_t: float = 0.0,
          restitution: str = "energetic", length: float = 1.0, mass: float = 1.0,
          angle: float = 0.5, vx: float = -1.0, g: float = 9.81, painleve: str = "impact"):
    """Rod on its lower end at the origin, tilted by ``angle``, sliding at ``vx``."""
    from rbimpact import Rod, Scene2D
    positive("painleve_rod", length=length, mass=mass)
    nonnegative("painleve_rod", g=g)
    if not 0.0 < angle < 0.5 * math.pi:
        raise ValueError(f"scenario 'painleve_rod': angle must be in (0, pi/2) rad, got "
                         f"{angle!r}")
    values = dict(law=law, e=e, mu=mu, e_t=e_t, restitution=restitution, length=length,
                  mass=mass, angle=angle, vx=vx, g=g, painleve=painleve)
    the_law = make_law(law, **law_params(values))
    half = 0.5 * length
    scene = Scene2D(gravity=(0.0, -g))
    floor = scene.add_floor(0.0)
    rod = scene.add_body(Rod(length), mass, (half * math.cos(angle), half * math.sin(angle)),
                         angle=angle, velocity=(vx, 0.0))
    ref = PainleveReference(angle, mu, vx, max(e, 0.0), half, mass)
    return Scenario("painleve_rod", DESCRIPTION, scene, the_law, None, 1.0, ALL_LAWS, values,
                    {"painleve": painleve}, ref, bodies={"rod": rod},
                    planes={"floor": floor})
