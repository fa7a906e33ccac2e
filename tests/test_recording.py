"""What a run keeps (issue 15, item 3): ``run(record=..., observer=..., snapshot_dt=...)`` of
``Simulation`` and ``Simulation3D``. Real scenes; the drain chunk (``_recording.DRAIN_ROWS``)
is made tiny so that a short run drains its buffers many times."""
import math
import warnings

import numpy as np
import pytest

from rbimpact import _recording, scenarios
from rbimpact._recording import NotRecordedError, Recorder
from rbimpact.laws import Law
from rbimpact.scene import Scene2D
from rbimpact.scene3d import Scene3D
from rbimpact.shapes import Disk, Rod
from rbimpact.shapes3d import Sphere
from rbimpact.simulation import Simulation

CHUNK = 4


@pytest.fixture
def small_chunk(monkeypatch):
    monkeypatch.setattr(_recording, "DRAIN_ROWS", CHUNK)


@pytest.fixture
def drains(monkeypatch):
    """Records the buffer lengths (events, segments) returned by every drain."""
    seen = []
    orig = Recorder.on_full

    def on_full(self, bufs, *args):
        out = orig(self, bufs, *args)
        seen.append((len(out[0]), len(out[3])))
        return out

    monkeypatch.setattr(Recorder, "on_full", on_full)
    return seen


def ball(e, h=0.3, law="kane_levinson"):
    scene = Scene2D(gravity=(0.0, -9.81))
    scene.add_floor()
    scene.add_body(Disk(0.05), 1.0, (0.0, h + 0.05), velocity=(0.2, 0.0),
                   angular_velocity=1.0)
    return Simulation(scene, Law(law, e=e, mu=0.3))


def two_disks():
    """Two disks bouncing on a floor between two walls: disk-disk, disk-wall and floor
    impacts, then rest."""
    scene = Scene2D(gravity=(0.0, -9.81))
    scene.add_floor()
    scene.add_plane((-0.5, 0.0), (1.0, 0.0))
    scene.add_plane((0.5, 0.0), (-1.0, 0.0))
    scene.add_body(Disk(0.05), 1.0, (-0.2, 0.3), velocity=(1.5, 0.0))
    scene.add_body(Disk(0.07), 2.0, (0.2, 0.2), velocity=(-1.0, 0.5))
    return Simulation(scene, Law("routh", e=0.9, mu=0.2))


def rod_pivot():
    """A spinning rod dropped on one end: impacts, then pivoting on an end (integrated,
    recorded as short pieces ahead of the loop's time), landing, rest."""
    scene = Scene2D(gravity=(0.0, -9.81))
    scene.add_floor()
    scene.add_body(Rod(1.0), 1.0, (0.0, 0.5), angle=0.5, angular_velocity=2.0)
    return Simulation(scene, Law("routh", e=0.5, mu=1.0))


def two_spheres():
    sc = Scene3D(gravity=(0.0, 0.0, -9.81))
    sc.add_floor()
    sc.add_plane((-0.5, 0.0, 0.0), (1.0, 0.0, 0.0))
    sc.add_plane((0.5, 0.0, 0.0), (-1.0, 0.0, 0.0))
    sc.add_body(Sphere(0.05), 1.0, (-0.2, 0.0, 0.3), velocity=(1.5, 0.01, 0.0))
    sc.add_body(Sphere(0.07), 2.0, (0.2, 0.0, 0.2), velocity=(-1.0, 0.0, 0.5))
    return Simulation(sc, Law("routh", e=0.9, mu=0.0))


# 2D: Zeno then rest (bouncing ball e = 0.9), pivot pieces recorded ahead of the loop's time
# (rod), disk-disk contacts; 3D: a tumbling die (integrated contacts), sphere-sphere contacts
SCENES = {
    "ball_e0.9": lambda: (ball(0.9, h=0.1), 6.0),
    "rod_pivot": lambda: (rod_pivot(), 3.0),
    "two_disks": lambda: (two_disks(), 10.0),
    "die_toss": lambda: (scenarios.get("die_toss", seed=1).simulation(), 3.0),
    "two_spheres": lambda: (two_spheres(), 2.0),
    "billiards": lambda: (scenarios.get("billiards").simulation(), 5.0),   # six disks
}


def final_state(res):
    s = res.sample([res.t_end])
    return {k: v[0] for k, v in s.items()}


def assert_same_state(a, b):
    assert a.keys() == b.keys()
    for k in a:
        np.testing.assert_array_equal(a[k], b[k], err_msg=k)


@pytest.mark.parametrize("name", [n for n in SCENES if n != "billiards"])
def test_record_none_gives_the_final_state_counts_and_every_event_to_the_observer(
        name, small_chunk, drains):
    sim, t_end = SCENES[name]()
    full = sim.run(t_end)
    assert full.n_events > 10 * CHUNK
    drains.clear()
    chunks = []
    res = sim.run(t_end, record="none", observer=chunks.append)
    assert len(drains) >= 10                                 # drained many times
    assert res.status == full.status == "done" and res.t_end == full.t_end
    assert res.n_events == full.n_events == len(full.events)
    assert res.n_impacts == full.n_impacts
    assert res.event_counts == {k: int(np.sum(full.events["kind"] == k))
                                for k in res.event_counts}
    assert sum(res.event_counts.values()) == res.n_events
    assert_same_state(final_state(res), final_state(full))
    # the observer saw every event once, in order, in chunks of at most the buffer's rows
    assert len(chunks) >= 10 and all(not c.flags.writeable for c in chunks)
    np.testing.assert_array_equal(np.concatenate(chunks), full.events)
    assert res.record == "none" and full.record == "all"


@pytest.mark.parametrize("name", ["two_disks", "two_spheres"])
def test_record_all_with_an_observer_is_the_plain_run(name, small_chunk):
    sim, t_end = SCENES[name]()
    plain = sim.run(t_end)
    chunks = []
    res = sim.run(t_end, observer=chunks.append)
    np.testing.assert_array_equal(res.events, plain.events)
    np.testing.assert_array_equal(np.concatenate(chunks), plain.events)
    t = np.linspace(0.0, t_end, 301)
    s, p = res.sample(t), plain.sample(t)
    assert_same_state(s, p)
    assert res.n_events == len(res.events) and res.kept_from(1) == 0.0


@pytest.mark.parametrize("name, keep", [("two_disks", [1]), ("billiards", [0, 3]),
                                        ("two_spheres", [0])])
def test_record_bodies_keeps_exactly_their_events_and_trajectories(name, keep, small_chunk):
    sim, t_end = SCENES[name]()
    full = sim.run(t_end)
    chunks = []
    res = sim.run(t_end, record=np.array(keep), observer=chunks.append)
    ev = full.events
    mine = np.isin(ev["a"], keep) | np.isin(ev["b"], keep)
    assert 0 < mine.sum() < len(ev)
    np.testing.assert_array_equal(res.events, ev[mine])
    np.testing.assert_array_equal(np.concatenate(chunks), ev)      # the observer sees all
    assert res.n_events == len(ev) and res.n_impacts == full.n_impacts
    # the recorded bodies' whole trajectories, the others' final state
    t = np.linspace(0.0, full.t_end, 257)
    s = res.sample(t, bodies=keep)
    f = full.sample(t, bodies=keep)
    assert_same_state(s, f)
    for key in f:
        np.testing.assert_array_equal(f[key], full.sample(t)[key][:, keep])
    assert_same_state(final_state(res), final_state(full))
    others = [i for i in range(full.n_bodies) if i not in keep]
    assert all(res.kept_from(i) == 0.0 for i in keep)
    assert all(0.0 < res.kept_from(i) <= res.t_end for i in others)
    with pytest.raises(NotRecordedError, match=r"record=\[.*body %d's state is kept only "
                       r"from" % others[0]):
        res.sample([0.0])
    assert list(res.record) == sorted(keep)


def test_record_none_memory_stays_flat(small_chunk, drains):
    """An elastic ball: >= 10 chunks of events; the buffers keep their first capacity with
    record="none" (and grow with record="all")."""
    sim = ball(1.0, h=0.05)
    t_end = 100.0
    res = sim.run(t_end, record="none")
    assert res.n_events >= 10 * CHUNK * 10
    caps = set(drains)
    assert len(drains) >= res.n_events // (2 * CHUNK) and len(caps) == 1
    from rbimpact.kernels import stepper2d as k
    me = k.event_margin(np.full(k.N_TI, 1000), 1)
    cap_e, cap_s = caps.pop()
    assert cap_e == me + CHUNK and cap_s == k.segment_margin(1) + 1 + CHUNK
    drains.clear()
    full = sim.run(t_end)
    assert len(drains[-1]) and drains[-1][0] > cap_e                 # "all" grows
    assert_same_state(final_state(res), final_state(full))
    assert res.n_events == len(full.events)


def test_max_events_counts_every_event_with_record_none(small_chunk):
    sim = ball(1.0)
    with pytest.warns(RuntimeWarning, match="max_events=50"):
        full = sim.run(40.0, max_events=50)
    with pytest.warns(RuntimeWarning, match="max_events=50"):
        res = sim.run(40.0, max_events=50, record="none")
    assert res.status == full.status == "max_events"
    assert res.n_events == len(full.events) == 50
    assert res.t_end == full.t_end < 40.0
    assert_same_state(final_state(res), final_state(full))
    with pytest.warns(RuntimeWarning, match="max_events"):
        sub = sim.run(40.0, max_events=50, record=[0], snapshot_dt=0.5)
    np.testing.assert_array_equal(sub.events, full.events)
    assert sub.snapshots[0][-1] <= sub.t_end


@pytest.mark.parametrize("name", ["rod_pivot", "billiards", "die_toss", "two_spheres"])
@pytest.mark.parametrize("record", ["none", "all", [0]])
def test_snapshots_are_the_exact_states(name, record, small_chunk):
    sim, t_end = SCENES[name]()
    full = sim.run(t_end)
    dt = 0.0123
    res = sim.run(t_end, record=record, snapshot_dt=dt)
    t, states = res.snapshots
    n = math.floor(t_end / dt) + 1
    np.testing.assert_array_equal(t, np.arange(n) * dt)
    ref = full.sample(t)
    assert states.keys() == ref.keys()
    for key in ref:
        assert states[key].shape == ref[key].shape
        np.testing.assert_array_equal(states[key], ref[key], err_msg=key)   # bit for bit
    assert full.snapshots is None


def test_snapshots_reach_t_end_when_it_is_a_multiple_of_dt():
    res = ball(0.9).run(3.0, record="none", snapshot_dt=0.1)
    t, s = res.snapshots
    assert len(t) == 31 and t[-1] == pytest.approx(3.0, rel=1e-15)
    assert s["y"].shape == (31, 1)


def test_what_a_record_none_result_refuses(small_chunk, tmp_path):
    sim, t_end = SCENES["two_disks"]()
    res = sim.run(t_end, record="none")
    for call in (lambda: res.events, lambda: res.to_csv(tmp_path / "e.csv"),
                 lambda: res.to_json(tmp_path / "e.json"), lambda: res.plot(tmp_path / "p.png"),
                 lambda: res.energy([0.0]), lambda: res.sample([0.0, res.t_end])):
        with pytest.raises(NotRecordedError, match="record='none'"):
            call()
    assert res.energy([res.t_end]).shape == (1,)
    assert "events" in repr(res) and str(res.n_events) in repr(res)
    sub = sim.run(t_end, record=[0])
    with pytest.raises(NotRecordedError, match=r"plot needs the whole run.*record=\[0\]"):
        sub.plot(tmp_path / "p.png")
    sub.to_json(tmp_path / "s.json")
    import json
    assert json.loads((tmp_path / "s.json").read_text())["record"] == [0]


def test_an_observer_exception_stops_the_run(small_chunk):
    sim, t_end = SCENES["two_disks"]()
    seen = []

    def observer(chunk):
        seen.append(len(chunk))
        if len(seen) == 3:
            raise KeyboardInterrupt("stop here")

    with pytest.raises(KeyboardInterrupt, match="stop here"):
        sim.run(t_end, record="none", observer=observer)
    assert len(seen) == 3
    # the simulation is reusable afterwards
    assert sim.run(t_end, record="none").status == "done"


@pytest.mark.parametrize("kw, match", [
    ({"record": "some"}, r"Simulation\.run: record must be 'all', 'none' or a non-empty "
                         r"1-D array of body indices \(integers in 0\.\.1\), got 'some'"),
    ({"record": [2]}, r"record must be .* got \[2\]: 2 is not a body index"),
    ({"record": [-1]}, r"record must be .* got \[-1\]: -1 is not a body index of the scene "
                       r"\(planes are not recorded on their own\)"),
    ({"record": []}, r"record .* got \[\]: it is empty \(use record='none'"),
    ({"record": [[0, 1]]}, r"record .* an array of shape \(1, 2\) is not 1-D"),
    ({"record": [0.5]}, r"record .* its values are not integers \(dtype float64\)"),
    ({"record": [True]}, r"record .* booleans are not body indices"),
    ({"record": None}, r"record must be .* got None"),
    ({"observer": 3}, r"observer must be a callable .* or None, got 3"),
    ({"observer": "print"}, r"observer must be a callable .* got 'print'"),
    ({"snapshot_dt": 0.0}, r"snapshot_dt must be a positive finite time \(s\) or None, "
                           r"got 0\.0"),
    ({"snapshot_dt": -1}, r"snapshot_dt must be a positive .* got -1"),
    ({"snapshot_dt": math.nan}, r"snapshot_dt must be finite \(s\), got nan"),
    ({"snapshot_dt": math.inf}, r"snapshot_dt must be finite \(s\), got inf"),
    ({"snapshot_dt": "0.1"}, r"snapshot_dt must be a real number \(s\), got '0\.1'"),
    ({"snapshot_dt": 1e-12}, r"snapshot_dt = 1e-12 s would take 3e\+12 snapshots"),
])
def test_bad_arguments_raise_value_errors(kw, match):
    sim, _ = SCENES["two_disks"]()
    with pytest.raises(ValueError, match=match):
        sim.run(3.0, **kw)


def test_bad_arguments_3d_name_simulation3d():
    sim, _ = SCENES["two_spheres"]()
    with pytest.raises(ValueError, match=r"Simulation3D\.run: record must be .* got 'x'"):
        sim.run(1.0, record="x")
    with pytest.raises(ValueError, match=r"Simulation3D\.run: snapshot_dt must be"):
        sim.run(1.0, snapshot_dt=-0.1)


def test_sample_bodies_argument_is_checked():
    res = ball(0.9).run(0.5)
    with pytest.raises(ValueError, match=r"bodies must be body indices \(0\.\.0\), got \[1\]"):
        res.sample([0.1], bodies=[1])
    assert res.sample([0.1], bodies=[0])["x"].shape == (1, 1)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert res.kept_from(0) == 0.0
