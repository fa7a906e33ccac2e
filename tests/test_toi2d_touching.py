"""A feature touching a plane at a round-off rate (session 16): the 2D plane time of impact
(toi2d.plane_feature_toi) reads a touching rate within decisions.TOUCH_RTOL of its speed
scale as zero, and a gap acceleration at its round-off is zero in the stepper's holding
test (decisions.touching_accel)."""
import math

import numpy as np

from rbimpact.kernels import toi2d
from rbimpact.kernels.decisions import TOUCH_RTOL, touching_accel

INF = math.inf
L = 0.0643          # capsule half length (m), as the campaign scene 2:441169314
RAD = 0.0185        # its radius (m)
G = 9.81


def _toi(st, px, rad, S=1.0, maxit=1000):
    return toi2d.plane_feature_toi(toi2d.FEAT_VERTEX, np.asarray(st, float), px, 0.0, rad,
                                   0.0, 0.0, 1.0, 0.0, 0.0, 0.15, S, 1e-14, 1e-15, 1e-9,
                                   maxit)


def test_capsule_flat_on_a_wall_gravity_does_not_push_has_no_impact():
    """A capsule upright against the wall x = 0, sliding down it (gravity along the wall),
    its normal speed and spin at round-off: its ends touch at a round-off rate for the whole
    horizon, which is no impact (the search used to step toi_atol at a time and never end:
    2:441169314)."""
    st = [RAD, 0.2, 0.5 * math.pi, -1.5e-13, -0.97, -2.3e-12, 0.0, -G, 0.0]
    for px in (L, -L):
        s, code = _toi(st, px, RAD)
        assert code == toi2d.TOI_OK and s == INF


def test_rod_pivoting_on_its_end_meets_the_wall_when_its_rate_leaves_round_off():
    """A rod upright on the wall x = 0 turning about its lower end (that end's normal rate
    exactly 0, its gap acceleration 0 to round-off): its gap is -L (w s - sin w s), a
    third-order tangency, and its rate -L w (1 - cos w s) passes -thr (thr = TOUCH_RTOL
    times the speed scale) at s* = sqrt(2 thr / (L w^3)). The search steps there at once
    (from the gap acceleration at 0 and the bound L w^3 of its derivative; a step from the
    bound M of the gap acceleration alone, thr / M, needs ~1e5 steps) and reports the
    impact there, the gap -L (w s*)^3 / 6."""
    w = 0.186
    st = np.array([0.0, 0.2, 0.5 * math.pi, -w * L, -0.97, w, 0.0, -G, 0.0])
    thr = TOUCH_RTOL * toi2d._touching_scale(st, L, L)
    s_star = math.sqrt(2.0 * thr / (L * w ** 3))
    s, code = _toi(st, -L, 0.0, maxit=50)
    assert code == toi2d.TOI_OK
    assert s_star * (1.0 - 1e-6) <= s <= 1.5 * s_star, (s, s_star)
    g, gd = toi2d.vertex_gap(st, -L, 0.0, 0.0, 1.0, 0.0, 0.0, s)
    assert gd < -(1.0 - 1e-6) * thr
    # to the round-off of L cos(angle) near pi / 2 (1e-16 L)
    assert math.isclose(g, -L * (w * s) ** 3 / 6.0, abs_tol=2e-16 * L), g


def test_touching_accel_removes_round_off_only():
    # scale: |a| + w^2 reach = 9.81 + 4 * 0.1 = 10.21 m/s^2
    assert touching_accel(-1.4e-20, G, 2.0, 0.1) == 0.0
    assert touching_accel(-TOUCH_RTOL * 10.2, G, 2.0, 0.1) == 0.0
    assert touching_accel(-TOUCH_RTOL * 10.3, G, 2.0, 0.1) == -TOUCH_RTOL * 10.3
    assert touching_accel(-0.5, G, 2.0, 0.1) == -0.5
    assert touching_accel(3.0, 0.0, 0.0, 0.1) == 3.0
