"""3D time of impact from a feature touching a plane at a round-off rate (session 16,
branch toi3d-roundoff): toi3d.body_planes_toi steps over it by the time its rate needs to
fall below -thr (toi3d._round_off_rate_time), not by safe steps from a gap clamped to 0."""
import math

import numpy as np

from rbimpact import campaign
from rbimpact.kernels import flight3d, toi3d
from rbimpact.kernels.decisions import TOUCH_RTOL

L = 0.25        # the feature's arm (m)
G = 9.81


def _toi(g0, rate, w, maxit):
    """A point at arm (0, -L, 0) of a body with spherical inertia, touching the wall x = 0
    (normal +x), turning about z at w (rad/s), its normal rate ``rate`` (m/s), gravity
    along -y: its gap is g0 + rate s - L (w s - sin w s) for w > 0 (penetrating at third
    order), + L (|w| s - sin |w| s) for w < 0 (separating)."""
    row = np.zeros(19)
    row[0:3] = (g0, 0.2, 0.0)
    row[3] = 1.0                                   # identity orientation
    row[7:10] = (rate - w * L, -0.97, 0.0)         # w x r = (w L, 0, 0)
    row[10:13] = (0.0, 0.0, w)
    row[13:16] = (0.0, -G, 0.0)
    feats = np.array([[0.0, -L, 0.0]])
    planes = np.array([[1.0, 0.0, 0.0, 0.0]])
    ws = np.zeros(flight3d.N_WS)
    ws[flight3d.WS_MODE] = -1.0
    return toi3d.body_planes_toi(row, flight3d.ROT_SPHERICAL, 0, 1.0, 1.0, 1.0, ws, feats, 0,
                                 1, 0.0, planes, np.zeros(1, np.int64), 0.5, 1.0, 1e-14,
                                 1e-15, 1e-9, maxit, 1e-12, 100000, np.zeros(19))


def test_point_inside_by_round_off_and_separating_at_third_order_has_no_impact():
    """3:3522406362: a box corner released from a pivot, 7.8e-13 m inside the floor at
    +1.9e-11 m/s, its gap acceleration 0: the gap climbs back at third order. Safe steps
    from a gap clamped to 0 crept by 2 g' / M (1.8e-13 s) and never reached it; the
    round-off-rate step sees that its rate cannot fall below -thr and finds no impact."""
    s, p, k, code = _toi(-7.8e-13, 1.9e-11, -18.0, maxit=1000)
    assert code == toi3d.TOI_OK and s == math.inf, (s, code)


def test_point_touching_and_penetrating_at_third_order_meets_the_wall_at_s_star():
    """The same point turning the other way (its gap -L (w s - sin w s)): its rate passes
    -thr at s* = sqrt(2 thr / (L w^3)), where the search reports the impact, in a few
    steps."""
    w = 18.0
    s, p, k, code = _toi(0.0, 0.0, w, maxit=100)
    assert code == toi3d.TOI_OK and (p, k) == (0, 0)
    speed = math.hypot(0.97, w * L) + w * L     # centre speed + |w x r| at s = 0
    thr = TOUCH_RTOL * (speed + math.sqrt(G * L))
    s_star = math.sqrt(2.0 * thr / (L * w ** 3))
    assert 0.9 * s_star <= s <= 1.5 * s_star, (s, s_star)


def test_box_released_from_a_pivot_ends_done():
    """3:3522406362 (Routh-Poisson e = 0, mu = 1): 'did not converge in toi_max_iter'
    after its release from a pivot; done now, no sinking, no energy gain."""
    row = campaign.run_drop(3, 3522406362)
    assert row.verdict == "OK", row.note
    assert row.penetration <= row.pen_tol and row.energy_gain < 1e-10
