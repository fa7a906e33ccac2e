"""The event loop's guard against running without end (``idle_passes``): a run whose passes
record no event (integrated motion, bounded searches) stops with status "idle" and a
message that says so, instead of running on; a scene within the budget is unchanged.

Real physics that can fail: the scenes are long integrated motions with no event (a rough
ellipse rocking by rolling, 2D; two spheres rolling together after a push, a moving
cluster, 3D). With a budget below their pass count they must stop
with the named status and the partial result up to that point, identical to the full
run's; with the default they must run to the end."""
import math

import numpy as np
import pytest

from rbimpact import Ellipse, Law, Scene2D, Scene3D, Simulation, SimulationError, Sphere

G = 9.81


def _rocking_ellipse(**tol):
    """A rough ellipse (semi-axes 0.2 m, 0.1 m, 1 kg) set down tilted by 0.5 rad: it rolls
    without slip and rocks for ever (no event after its first pivot)."""
    a, b = 0.2, 0.1
    sc = Scene2D(gravity=(0.0, -G))
    sc.add_floor(0.0)
    h = math.sqrt(a * a * math.sin(0.5) ** 2 + b * b * math.cos(0.5) ** 2)
    sc.add_body(Ellipse(a, b), 1.0, (0.0, h), angle=0.5)
    return Simulation(sc, Law("routh", e=0.0, mu=10.0), **tol)


def _rolling_pair(**tol):
    """Sphere 0 (r 0.1 m, 1 kg) rolling at 1 m/s into sphere 1 at rest (frictionless
    plastic pair, floor mu 0.3): after the push they roll together at 0.5 m/s for ever, a
    moving cluster whose passes meet no event."""
    sc = Scene3D(gravity=(0.0, 0.0, -G))
    sc.add_floor()
    r = 0.1
    sc.add_body(Sphere(r), 1.0, (0.0, 0.0, r), velocity=(1.0, 0.0, 0.0),
                angular_velocity=(0.0, 1.0 / r, 0.0))
    sc.add_body(Sphere(r), 1.0, (2.3 * r, 0.0, r))
    return Simulation(sc, Law("kane_levinson", e=0.0, mu=0.3),
                      {(0, 1): Law("kane_levinson", e=0.0, mu=0.0)}, **tol)


def _passes_needed(make, t_end):
    """The smallest idle_passes this scene runs to t_end with (by bisection on the status:
    a run stops with 'idle' exactly when its longest stretch without an event takes more
    passes than the budget)."""
    lo, hi = 0, 1
    while True:
        try:
            make(idle_passes=hi).run(t_end)
            break
        except SimulationError as exc:
            assert exc.result.status == "idle", str(exc)
            lo, hi = hi, 2 * hi
    while hi - lo > 1:
        mid = (lo + hi) // 2
        try:
            make(idle_passes=mid).run(t_end)
            hi = mid
        except SimulationError:
            lo = mid
    return hi


@pytest.mark.parametrize("make, t_end", [(_rocking_ellipse, 5.0), (_rolling_pair, 20.0)],
                         ids=["2d-rocking-ellipse", "3d-rolling-pair"])
def test_a_run_that_records_no_event_stops_with_status_idle(make, t_end):
    full = make().run(t_end)
    assert full.status == "done"
    need = _passes_needed(make, t_end)
    assert need >= 3        # the motion takes several passes with no event between them
    with pytest.raises(SimulationError) as info:
        make(idle_passes=need - 1).run(t_end)
    exc = info.value
    assert exc.result.status == "idle"
    msg = str(exc)
    assert f"{need - 1} consecutive passes" in msg and "no event" in msg
    assert "raise idle_passes" in msg
    # the partial result stops before t_end and agrees with the full run where it reaches
    part = exc.result
    assert 0.0 < part.t_end < t_end
    ts = np.linspace(0.0, part.t_end, 51)
    np.testing.assert_allclose(part.energy(ts), full.energy(ts), rtol=0, atol=1e-12)
