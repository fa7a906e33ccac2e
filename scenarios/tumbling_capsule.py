"""tumbling_capsule: a capsule thrown tumbling onto a rough floor; with Routh's law the
slip direction swerves during each impact."""
import math

import numpy as np

from . import ALL_LAWS, law_params, make_law, nonnegative, positive, register
from .die_toss import Scenario3D

DESCRIPTION = """\
A uniform capsule (cylinder `length` m between the centres of its hemispherical caps,
radius `radius` m, mass `mass` kg, axis along its body z axis) is thrown from height
`height` (m, its centre) with its axis tilted by `tilt` (rad) from the vertical, velocity
`speed` (m/s) along +x and angular velocity `spin` (rad/s) about an axis oblique to its
own (`spin_axis` = "oblique": (1, 1, 1)/sqrt 3 in the world). It lands on its caps; at a
cap the Delassus matrix W couples the normal to both tangential directions, so under
Routh's law the slip direction *swerves* during the impact (DESIGN §4, 3D): the final
tangential velocity is not along the initial one (nor opposite to it).
`reference.swerve(result)` gives, per impact, the angle (degrees) between the initial
and the final slip of the contact point. Later the capsule rocks on its caps, lies down
and rolls or rests on its side (integrated persistent contact)."""


class SwerveReference:
    """Angle between initial and final slip (degrees) of every impact with sliding."""

    @staticmethod
    def swerve(result, min_slip=1e-9):
        imp = result.events[result.events["kind"] == "impact"]
        a = imp["v_i"][:, 1:]
        b = imp["v_f"][:, 1:]
        na = np.linalg.norm(a, axis=1)
        nb = np.linalg.norm(b, axis=1)
        ok = (na > min_slip) & (nb > min_slip)
        cos = np.sum(a[ok] * b[ok], axis=1) / (na[ok] * nb[ok])
        return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


@register("tumbling_capsule", laws=ALL_LAWS,
          summary="a tumbling capsule: Routh's slip direction swerves at its impacts",
          help={"length": "length of the cylinder between the cap centres (m), > 0",
                "radius": "capsule radius (m), > 0",
                "mass": "capsule mass (kg), > 0",
                "height": "initial height of the centre (m)",
                "tilt": "tilt of the axis from the vertical (rad)",
                "speed": "initial velocity along +x (m/s)",
                "spin": "angular speed about (1, 1, 1)/sqrt 3 (rad/s), >= 0",
                "g": "gravity (m/s^2), > 0",
                "t_end": "end time (s), > 0"})
def build(law: str = "routh", e: float = 0.6, mu: float = 0.4, e_t: float = 0.0,
          restitution: str = "energetic", length: float = 0.1, radius: float = 0.02,
          mass: float = 0.1, height: float = 0.3, tilt: float = 0.6, speed: float = 1.0,
          spin: float = 15.0, g: float = 9.81, t_end: float = 2.0):
    """Capsule thrown tumbling onto the floor z = 0."""
    from rbimpact.scene3d import Scene3D
    from rbimpact.shapes3d import Capsule
    positive("tumbling_capsule", length=length, radius=radius, mass=mass, g=g, t_end=t_end)
    nonnegative("tumbling_capsule", spin=spin)
    reach = 0.5 * length * abs(math.cos(tilt)) + radius
    if not height > reach:
        raise ValueError(f"scenario 'tumbling_capsule': height must be > {reach:g} m (the "
                         f"capsule must start above the floor), got {height!r}")
    values = dict(law=law, e=e, mu=mu, e_t=e_t, restitution=restitution, length=length,
                  radius=radius, mass=mass, height=height, tilt=tilt, speed=speed, spin=spin,
                  g=g, t_end=t_end)
    the_law = make_law(law, **law_params(values))
    scene = Scene3D(gravity=(0.0, 0.0, -g))
    floor = scene.add_floor(0.0)
    # tilt the body z axis by `tilt` about the world y axis
    q = (math.cos(0.5 * tilt), 0.0, math.sin(0.5 * tilt), 0.0)
    w = spin / math.sqrt(3.0)
    cap = scene.add_body(Capsule(length, radius), mass, (0.0, 0.0, height), orientation=q,
                         velocity=(speed, 0.0, 0.0), angular_velocity=(w, w, w))
    return Scenario3D("tumbling_capsule", DESCRIPTION, scene, the_law, None, t_end, ALL_LAWS,
                      values, {}, SwerveReference(), bodies={"capsule": cap},
                      planes={"floor": floor})
