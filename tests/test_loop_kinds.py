"""The scene loop and the general loop (``rbimpact._setup.LOOP_KINDS``, issue 14) give the
same run bit for bit: the scene loop only prunes the laws a scene does not use and the
modes it cannot reach (``stepper2d.scene_features``, ``stepper3d.scene_features``). The
scenes are campaign draws of the extreme feature patterns in each dimension: no mode at
all, a body held by two planes or on a face, and a pair of other shapes than two disks or
spheres (every switch of the 3D loop on). The test suite runs the general loop
(tests/conftest.py); this is what makes that run stand for the scene loops users run."""
import numpy as np
import pytest

from rbimpact import campaign as C
from rbimpact._setup import LOOP_ENV, loop_kind
from rbimpact.kernels import stepper2d, stepper3d

#: (dim, bodies, scene seed, its feature switches): campaign scenes of seed 2026
SCENES = [
    (2, 1, 942662196, (None, None, None, None, None)),      # a disk on a floor (C&R)
    (2, 1, 3397492307, (True, True, None, True, True)),     # a rod in a corner (C&R)
    (2, 2, 1467416253, (True, None, "all", True, True)),    # an ellipse meets a polygon
    (3, 1, 1103301753, (None, None, None, None)),           # a sphere bounces (Routh)
    (3, 1, 2767302422, (True, None, None, True)),           # a box bounces (Routh)
    (3, 2, 1691185845, (True, True, True, True)),           # a capsule meets a box (Routh)
]


def _run(dim, bodies, sseed, kind):
    spec = (C.draw_pair_scene if bodies == 2 else C.draw_scene)(dim, sseed)
    sim, t_end, max_events = (C.build_pair_scene if bodies == 2 else C.build_scene)(spec)
    sim.loop = kind
    return sim, sim.run(t_end, max_events=max_events)


@pytest.mark.parametrize("dim, bodies, sseed, switches", SCENES)
def test_scene_loop_and_general_loop_run_the_same(dim, bodies, sseed, switches):
    k = stepper2d if dim == 2 else stepper3d
    sim, a = _run(dim, bodies, sseed, "scene")
    assert k.scene_features(sim._bint, sim._planes, sim._grav, len(sim._pairs)) == switches
    _, b = _run(dim, bodies, sseed, "general")
    assert a.status == b.status == "done"
    assert a.n_impacts > 0 and a.n_impacts == b.n_impacts
    # bit for bit: every event (time, bodies, point, velocities, impulses) and every
    # trajectory segment (the state each flight starts from)
    for x, y in zip(_arrays(a), _arrays(b)):
        assert x.shape == y.shape and np.array_equal(x, y)


def _arrays(res):
    """Every field of the events and the trajectory segments' times and states."""
    ev = res.events
    if hasattr(res, "_segments"):
        res._segments()
    return [ev[f] for f in ev.dtype.names] + [res._seg_t, res._seg_s]


def test_loop_kind_comes_from_the_environment_and_is_checked(monkeypatch):
    monkeypatch.setenv(LOOP_ENV, "scene")
    assert loop_kind() == "scene"
    monkeypatch.delenv(LOOP_ENV)
    assert loop_kind() == "scene"
    monkeypatch.setenv(LOOP_ENV, "fast")
    with pytest.raises(ValueError, match=r"\$RBIMPACT_LOOP must be one of 'scene', 'general'"):
        loop_kind()
    with pytest.raises(ValueError, match="drop_campaign: loop must be one of"):
        C.drop_campaign(1, dim=2, loop="all")
    spec = C.draw_scene(2, 942662196)
    sim, _, _ = C.build_scene(spec)
    with pytest.raises(ValueError, match="Simulation: loop must be one of 'scene', 'general'"):
        type(sim)(sim.scene, sim.law, loop="fast")
