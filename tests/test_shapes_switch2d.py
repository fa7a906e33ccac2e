"""The 2D loop's ``shapes`` switch (issue 14): a scene of disks only compiles a loop without
the polygon and ellipse branches of the persistent-contact and time-of-impact code, with
results bit for bit those of the general loop."""
import numpy as np
import pytest

from rbimpact.errors import SimulationError
from rbimpact.kernels import stepper2d as k
from rbimpact.laws import Law
from rbimpact.scene import Scene2D
from rbimpact.shapes import Box, Disk
from rbimpact.simulation import Simulation

G0 = 9.80665


def _sim(shape, vx=0.0, mu=0.3, e=0.8):
    scene = Scene2D(gravity=(0.0, -G0))
    scene.add_floor(0.0)
    scene.add_body(shape, 1.0, (0.0, 1.05), velocity=(vx, 0.0))
    return Simulation(scene, Law("kane_levinson", e=e, mu=mu))


def _features(sim):
    return k.scene_features(sim._bint, sim._planes, sim._grav, len(sim._pairs))


def _with_loop(sim, shapes):
    """Run ``sim`` with its scene's loop, but the ``shapes`` switch forced."""
    law = int(sim._law_ids[0])
    sim._loop_switches = (k.loop_for(law, *_features(sim)[:4], shapes), ())
    return sim


def test_scene_features_shapes():
    assert _features(_sim(Disk(0.05)))[4] is None
    assert _features(_sim(Box(0.1, 0.05)))[4] is True


@pytest.mark.parametrize("vx, mu, e", [(1.0, 0.3, 0.8), (0.0, 0.0, 1.0), (2.0, 0.05, 0.5)])
def test_disk_loop_is_the_general_loop(vx, mu, e):
    """Bounces, accumulation, sliding then rolling: the same events, bit for bit."""
    runs = []
    for shapes in (None, True):
        sim = _with_loop(_sim(Disk(0.05), vx=vx, mu=mu, e=e), shapes)
        res = sim.run(3.0, max_events=500)
        runs.append((np.asarray(res.events).tobytes(), res.n_impacts))
    assert runs[0] == runs[1]


def test_disk_loop_refuses_other_shapes():
    """A box in a loop compiled for disks only is an internal error, never a silent disk."""
    sim = _with_loop(_sim(Box(0.1, 0.05)), None)
    with pytest.raises(SimulationError, match="internal error"):
        sim.run(1.0)
