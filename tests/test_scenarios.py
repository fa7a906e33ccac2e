"""The scenario library (rbimpact.scenarios) and the `rbimpact run` / `rbimpact list` logic.

Every scenario runs to its end for every law it declares, with finite state and no energy
created by laws that never create it; scenario-specific physics is checked against exact
references (bouncing ball impact times, first-impact times) or qualitative facts that the
law decides (the superball comes back only with tangential restitution; a perforating
body ends beyond the barrier, slower).
"""
import csv
import json
import math
import subprocess
import sys

import numpy as np
import pytest

from rbimpact import scenarios
from rbimpact.run import list_text, run_scenario

NAMES = ("billiards", "bouncing_ball", "bouncing_ellipse", "box_on_box", "box_stack", "dominoes",
         "falling_rod",
         "painleve_rod", "perforation", "polygon_collide", "rocking_block", "rod_strikes_ball",
         "spinning_ball", "superball")
# the 3D scenarios (tests/test_stepper3d.py and tests/test_stepper_pairs3d.py run them)
NAMES_3D = ("dice_collide", "die_toss", "spinning_ball_3d", "superball_3d",
            "tumbling_capsule")
# many-body scenarios (granular_gas: rbimpact.manybody, tests/test_gas_physics.py;
# polygon_gas: the 2D stepper, tests/test_polygon_gas.py)
NAMES_MANY = ("granular_gas", "polygon_gas")
CASES = [(name, law) for name in NAMES for law in scenarios.spec(name).laws]

# scenarios that start at rest and stay there (no energy to dissipate)
AT_REST = ("box_stack",)
# Energy may not rise between two samples by more than this fraction of the run's energy
# scale (J): flight conserves it exactly (round-off ~1e-15), persistent sliding dissipates,
# a Zeno snap changes it by at most m g rest_length (~1e-9 J).
ENERGY_RTOL = 1e-9


def _run(sc, **kw):
    return sc.simulate(**kw)


def _times(result, n=2000):
    """A dense grid over the run plus every event time (sampled just after the event)."""
    t = np.linspace(result.t_start, result.t_end, n)
    ev = result.events["t"]
    return np.union1d(t, ev[(ev >= result.t_start) & (ev <= result.t_end)])


def _mid(t0, t1):
    return 0.5 * (t0 + t1)


# ------------------------------------------------------------------ every scenario, every law

@pytest.fixture(scope="module")
def runs():
    """Run every (scenario, law) once, with default parameters; cache the results."""
    cache = {}

    def get(name, law):
        if (name, law) not in cache:
            sc = scenarios.get(name, law=law)
            cache[name, law] = (sc, _run(sc))
        return cache[name, law]
    return get


@pytest.mark.parametrize("name,law", CASES)
def test_runs_to_end_finite_and_no_energy_created(runs, name, law):
    sc, r = runs(name, law)
    assert r.status == "done"
    assert r.t_end == pytest.approx(sc.t_end, rel=0, abs=1e-12)
    assert r.n_impacts >= 1
    t = _times(r)
    s = r.sample(t)
    for key, a in s.items():
        assert a.shape == (t.size, len(sc.scene.bodies))
        assert np.all(np.isfinite(a)), f"{name}/{law}: non-finite {key}"
    ev = r.events
    for f in ("t", "point", "normal", "v_i", "v_f", "P", "dE"):
        assert np.all(np.isfinite(ev[f])), f"{name}/{law}: non-finite event field {f}"
    assert np.all(np.diff(ev["t"]) >= 0)
    E = r.energy(t)
    assert np.all(np.isfinite(E))
    if sc.law.may_create_energy:
        return
    scale = float(np.max(np.abs(E)))
    rise = np.diff(E)
    k = int(np.argmax(rise))
    assert rise[k] <= ENERGY_RTOL * scale, (
        f"{name}/{law}: energy rose by {rise[k]:.3g} J between t = {t[k]:.9g} and "
        f"{t[k + 1]:.9g} s (scale {scale:.3g} J)")
    imp = ev[ev["kind"] == "impact"]
    # each impact's work P . (v_i + v_f) / 2 against 1e-12 of its instant's (the impacts at
    # one t): in a joint impact a contact at rest (v ~ 1e-20 m/s) takes velocity from the
    # others' impulses, its own work a round-off of theirs (dominoes, Smith)
    own = 0.5 * np.sum(np.abs(imp["P"]) * (np.abs(imp["v_i"]) + np.abs(imp["v_f"])), axis=1)
    _, inst = np.unique(imp["t"], return_inverse=True)
    bound = 1e-12 * np.bincount(inst, weights=own)[inst]
    assert np.all(imp["dE"] <= bound), f"{name}/{law}: an impact created energy"
    if name in AT_REST:
        assert E[-1] <= E[0]
    else:
        assert E[-1] < E[0]  # every other scenario dissipates with its default parameters


def test_every_scenario_is_registered_with_its_laws():
    assert scenarios.names() == tuple(sorted(NAMES + NAMES_3D + NAMES_MANY))
    for name in NAMES:
        s = scenarios.spec(name)
        assert s.default_law in s.laws
        assert set(s.laws) <= set(scenarios.ALL_LAWS)
        assert s.summary and s.params["law"].choices == s.laws
    assert scenarios.spec("perforation").laws == ("brach",)
    assert scenarios.spec("superball").default_law == "chatterjee_ruina"
    assert scenarios.spec("falling_rod").laws == scenarios.ALL_LAWS


@pytest.mark.parametrize("name", NAMES)
def test_scenario_object(name):
    sc = scenarios.get(name)
    assert sc.name == name
    assert len(sc.description) > 100
    assert sc.law.name == scenarios.spec(name).default_law
    assert sc.laws == scenarios.spec(name).laws
    assert sc.t_end > 0 and math.isfinite(sc.t_end)
    assert dict(sc.params) == {k: p.default for k, p in scenarios.spec(name).params.items()}
    assert set(sc.bodies.values()) == set(range(len(sc.scene.bodies)))
    with pytest.raises(AttributeError):
        sc.t_end = 1.0  # frozen
    assert scenarios.get(name).scene is not sc.scene  # built afresh by every get()


# ------------------------------------------------------------------ scenario physics

@pytest.mark.parametrize("law", scenarios.ALL_LAWS)
def test_bouncing_ball_impact_times_exact(runs, law):
    sc, r = runs("bouncing_ball", law)
    ref = sc.reference
    assert ref.t1 == pytest.approx(0.451600756, abs=1e-9)
    assert ref.t_inf == pytest.approx(4.064406802, abs=1e-9)
    imp = r.events[r.events["kind"] == "impact"]
    exact = ref.impact_times(30)
    assert len(imp) >= 30
    assert np.max(np.abs(imp["t"][:30] - exact) / exact) < 1e-10
    # every impact is on the floor, and the normal speeds follow e^k
    assert np.all(imp["b"] == -1 - sc.planes["floor"].index)
    assert np.allclose(-imp["v_i"][:30, 0], ref.impact_speeds(30), rtol=1e-9)


def test_bouncing_ball_other_parameters_and_rest():
    sc = scenarios.get("bouncing_ball", e=0.5, h=2.0, radius=0.2, g=9.81, mass=3.0,
                       law="kane_levinson")
    assert sc.scene.bodies[0].position[1] == pytest.approx(2.2)
    r = _run(sc)
    ref = sc.reference
    imp = r.events[r.events["kind"] == "impact"]
    exact = ref.impact_times(min(30, len(imp)))
    assert np.max(np.abs(imp["t"][:exact.size] - exact) / exact) < 1e-10
    contact = r.events[r.events["kind"] == "contact"]
    assert len(contact) == 1 and abs(contact["t"][0] - ref.t_inf) < 1e-6
    s = r.sample(np.linspace(ref.t_inf + 1e-3, r.t_end, 50))
    assert np.allclose(s["y"], 0.2, atol=1e-9)
    assert np.allclose(s["vy"], 0.0, atol=1e-9)
    assert r.t_end == pytest.approx(ref.t_inf + 1.0)


def test_bouncing_ball_elastic_conserves_energy():
    sc = scenarios.get("bouncing_ball", elastic=True, e=0.3, mu=0.5)
    assert sc.law.params_dict["e"] == 1.0 and sc.law.params_dict["mu"] == 0.0
    assert sc.params["e"] == 1.0 and math.isinf(sc.reference.t_inf)
    r = _run(sc, t_end=50.0)
    E = r.energy(_times(r))
    assert np.ptp(E) <= 1e-9 * E[0]
    imp = r.events[r.events["kind"] == "impact"]
    period = 2.0 * sc.reference.t1
    assert np.allclose(np.diff(imp["t"]), period, rtol=1e-9)
    assert len(imp) == int((50.0 - sc.reference.t1) // period) + 1


def test_spinning_ball_bounces_forward_and_backward(runs):
    for law in scenarios.spec("spinning_ball").laws:
        sc, r = runs("spinning_ball", law)
        top, back = sc.bodies["topspin"], sc.bodies["backspin"]
        vx0 = sc.params["vx"]
        for body, sign in ((top, +1), (back, -1)):
            imp = r.events[(r.events["kind"] == "impact") & (r.events["a"] == body)]
            t1, t2 = imp["t"][:2]
            vx = r.sample([_mid(t1, t2)])["vx"][0, body]
            if sign > 0:
                assert vx > vx0 + 0.5, f"{law}: topspin ball not thrown forward ({vx})"
            else:
                assert vx < -0.5, f"{law}: backspin ball does not bounce backward ({vx})"


def _table_bounce_vx(sc, r):
    """Horizontal velocity of the ball in flight before and after its first table bounce."""
    table = -1 - sc.planes["table"].index
    ev = r.events
    k = int(np.flatnonzero((ev["kind"] == "impact") & (ev["b"] == table))[0])
    t_prev = ev["t"][k - 1]
    t_next = ev["t"][k + 1] if k + 1 < len(ev) else r.t_end
    s = r.sample([_mid(t_prev, ev["t"][k]), _mid(ev["t"][k], t_next)])
    assert ev["normal"][k, 1] == pytest.approx(-1.0)
    return s["vx"][0, 0], s["vx"][1, 0]


@pytest.mark.parametrize("law", ["chatterjee_ruina", "brach", "smith"])
def test_superball_comes_back_with_tangential_restitution(runs, law):
    # C&R and Brach through e_t = 0.95; Smith because with mu = 1 it reverses the slip
    sc, r = runs("superball", law)
    assert sc.law.params_dict.get("e_t", 0.95) == 0.95
    before, after = _table_bounce_vx(sc, r)
    assert before > 0.0 and after < 0.0, (before, after)
    # and it keeps going back: at the end it is behind its point of the table bounce
    ev = r.events
    k = np.flatnonzero(ev["b"] == -1 - sc.planes["table"].index)[0]
    assert r.sample([r.t_end])["x"][0, 0] < ev["point"][k, 0]


@pytest.mark.parametrize("law", ["routh", "kane_levinson"])
def test_superball_does_not_come_back_without_tangential_restitution(runs, law):
    sc, r = runs("superball", law)
    before, after = _table_bounce_vx(sc, r)
    assert before > 0.0 and after > 0.0, (before, after)


def test_superball_et_near_one_matches_two_dimensional_garwin():
    # A disk (I = m r^2 / 2) thrown without spin, C&R with e_t = 1 inside the cone:
    # vx -> v/3 at the floor, -> -7v/9 at the table (hand calculation).
    sc = scenarios.get("superball", e_t=1.0, mu=10.0, vx=1.5)
    r = _run(sc)
    ev = r.events[r.events["kind"] == "impact"]
    s = r.sample([_mid(ev["t"][0], ev["t"][1]), _mid(ev["t"][1], ev["t"][2])])
    assert s["vx"][0, 0] == pytest.approx(1.5 / 3.0, rel=1e-12)
    assert s["vx"][1, 0] == pytest.approx(-7.0 * 1.5 / 9.0, rel=1e-12)


def test_perforation_goes_through_slower(runs):
    sc, r = runs("perforation", "brach")
    p = sc.params
    imp = r.events[r.events["kind"] == "impact"]
    assert len(imp) == 1
    assert imp["v_i"][0, 0] < 0 and imp["v_f"][0, 0] < 0  # still moving into the barrier
    assert imp["v_f"][0, 0] == pytest.approx(-p["e"] * imp["v_i"][0, 0], rel=1e-12)
    assert imp["point"][0, 0] == pytest.approx(p["barrier"], abs=1e-12)
    s = r.sample([0.0, r.t_end])
    assert s["x"][1, 0] > p["barrier"] + p["radius"]
    speed = np.hypot(s["vx"][:, 0], s["vy"][:, 0])
    assert speed[0] == pytest.approx(p["speed"])
    assert speed[1] < speed[0]
    assert s["vx"][1, 0] > 0.0


def test_perforation_needs_brach():
    with pytest.raises(ValueError, match="brach"):
        scenarios.get("perforation", law="kane_levinson")


@pytest.mark.parametrize("name,params", [
    ("falling_rod", {}), ("falling_rod", {"angle": -0.3, "radius": 0.02}),
    ("rocking_block", {}), ("bouncing_ellipse", {"omega": 0.0}),
])
def test_first_impact_time_exact(name, params):
    sc = scenarios.get(name, **params)
    r = _run(sc, t_end=0.6)
    t1 = r.events["t"][r.events["kind"] == "impact"][0]
    assert t1 == pytest.approx(sc.reference.t1, rel=1e-9)


def test_falling_rod_clatters_on_alternate_ends(runs):
    sc, r = runs("falling_rod", "routh")
    imp = r.events[r.events["kind"] == "impact"]
    assert len(imp) >= 10
    x = r.sample(imp["t"])["x"][:, 0]
    side = np.sign(imp["point"][:, 0] - x)
    assert np.count_nonzero(side[1:] != side[:-1]) >= 5


def test_rocking_block_rocks_from_corner_to_corner(runs):
    sc, r = runs("rocking_block", "routh")
    imp = r.events[r.events["kind"] == "impact"]
    x = r.sample(imp["t"])["x"][:, 0]
    side = np.sign(imp["point"][:, 0] - x)
    assert np.count_nonzero(side[1:] != side[:-1]) >= 5
    assert np.all(np.abs(r.sample(_times(r))["angle"][:, 0]) < math.atan2(0.4, 0.4))


@pytest.mark.parametrize("name", ["falling_rod", "bouncing_ellipse", "rocking_block",
                                  "spinning_ball"])
def test_kane_levinson_equals_brach_with_zero_tangential_restitution(runs, name):
    # DESIGN §4: in 2D, Brach with e_t = 0 coincides with Kane & Levinson, impact by impact
    # (also a guard against a stale compiled kernel inside the stepper)
    _, a = runs(name, "kane_levinson")
    _, b = runs(name, "brach")
    assert len(a.events) == len(b.events)
    assert np.allclose(a.events["t"], b.events["t"], rtol=1e-12, atol=0)
    assert np.allclose(a.events["P"], b.events["P"], rtol=1e-9, atol=1e-12)


def test_billiards_laws_agree_without_friction(runs):
    sc0, r0 = runs("billiards", "routh")
    assert sc0.pair_laws and all(x.params_dict["e"] == 0.85 for x in sc0.pair_laws.values())
    assert np.any(r0.events["b"] >= 0) and np.any(r0.events["b"] < 0)  # balls and cushions
    for law in scenarios.spec("billiards").laws:
        _, r = runs("billiards", law)
        assert len(r.events) == len(r0.events)
        assert np.allclose(r.events["t"], r0.events["t"], rtol=1e-12, atol=0)
        assert np.array_equal(r.events["a"], r0.events["a"])
        assert np.allclose(r.events["P"][:, 1], 0.0, atol=1e-15)


def test_billiards_elastic_conserves_kinetic_energy():
    r = _run(scenarios.get("billiards", e=1.0, e_cushion=1.0, n_balls=3))
    E = r.energy(_times(r))
    assert r.n_impacts >= 5
    assert np.ptp(E) <= 1e-12 * E[0]


# ------------------------------------------------------------------ registry and parameters

def test_unknown_scenario_lists_the_known_ones():
    with pytest.raises(ValueError, match="unknown scenario 'nope'.*bouncing_ball"):
        scenarios.get("nope")


def test_unknown_parameter_lists_the_allowed_ones():
    with pytest.raises(ValueError) as info:
        scenarios.get("bouncing_ball", height=2.0)
    msg = str(info.value)
    assert "no parameter 'height'" in msg
    for key in ("e (float", "h (float", "radius (float", "elastic (bool", "law (str"):
        assert key in msg


@pytest.mark.parametrize("params,match", [
    ({"e": "0.5"}, "'e' must be a float"),
    ({"elastic": 1}, "'elastic' must be a bool"),
    ({"n_balls": 2.0}, "'n_balls' must be a int"),
    ({"law": 3}, "'law' must be a str"),
    ({"e": float("nan")}, "finite"),
])
def test_ill_typed_parameters(params, match):
    name = "billiards" if "n_balls" in params else "bouncing_ball"
    with pytest.raises(ValueError, match=match):
        scenarios.get(name, **params)


@pytest.mark.parametrize("name,params,match", [
    ("bouncing_ball", {"law": "newton"}, "supports the laws"),
    ("bouncing_ball", {"restitution": "elastic"}, "energetic, poisson, newton"),
    ("bouncing_ball", {"radius": -1.0}, "radius must be > 0"),
    ("bouncing_ball", {"e": 1.5}, "'e' must be finite and in"),
    ("falling_rod", {"height": 0.1}, "start above the floor"),
    ("superball", {"y0": 0.9}, "y0 < table - radius"),
    ("billiards", {"n_balls": 40}, "n_balls"),
])
def test_bad_values_are_clear(name, params, match):
    with pytest.raises(ValueError, match=match) as info:
        scenarios.get(name, **params)
    assert f"scenario {name!r}" in str(info.value)


def test_integer_and_numpy_values_are_accepted():
    sc = scenarios.get("bouncing_ball", h=2, e=np.float64(0.5), mass=np.int64(2))
    assert sc.params["h"] == 2.0 and isinstance(sc.params["h"], float)
    assert sc.params["mass"] == 2.0
    assert scenarios.get("billiards", n_balls=np.int64(3)).params["n_balls"] == 3


def test_law_swap_keeps_collision_parameters():
    sc = scenarios.get("falling_rod", law="smith", e=0.7, mu=0.2, e_t=0.4)
    assert sc.law.name == "smith" and dict(sc.law.params_dict) == {"e": 0.7, "mu": 0.2}
    sc = scenarios.get("falling_rod", law="chatterjee_ruina", e=0.7, mu=0.2, e_t=0.4)
    assert dict(sc.law.params_dict) == {"e": 0.7, "mu": 0.2, "e_t": 0.4}
    sc = scenarios.get("falling_rod", law="routh", restitution="poisson")
    assert sc.law.params_dict["restitution"] == "poisson"
    assert sc.law.params_dict["e"] == 0.8


def test_parse_settings():
    got = scenarios.parse_settings("billiards", ["e=1", " n_balls = 3", "law=smith",
                                                 "aim=-0.02"])
    assert got == {"e": 1.0, "n_balls": 3, "law": "smith", "aim": -0.02}
    assert isinstance(got["e"], float) and isinstance(got["n_balls"], int)
    for text, value in (("yes", True), ("TRUE", True), ("0", False), ("off", False)):
        assert scenarios.parse_settings("bouncing_ball", [f"elastic={text}"]) == \
            {"elastic": value}
    assert scenarios.parse_settings("bouncing_ball", {"e": "0.25"}) == {"e": 0.25}


@pytest.mark.parametrize("settings,match", [
    (["e=fast"], "'e' must be a float, got 'fast'"),
    (["n_balls=2.5"], "'n_balls' must be an int"),
    (["elastic=maybe"], "true/false"),
    (["e"], "not of the form key=value"),
    (["colour=red"], "no parameter 'colour'"),
    (["e=inf"], "finite"),
    (["law=foo"], "one of kane_levinson"),
])
def test_parse_settings_errors(settings, match):
    name = "billiards" if "n_balls" in settings[0] else "bouncing_ball"
    if settings == ["elastic=maybe"]:
        name = "bouncing_ball"
    with pytest.raises(ValueError, match=match):
        scenarios.parse_settings(name, settings)


def test_register_rejects_bad_builders():
    with pytest.raises(TypeError, match="annotation"):
        @scenarios.register("_bad1", laws=("routh",), summary="x", help={})
        def bad1(law: str = "routh", x=1.0):
            pass
    with pytest.raises(TypeError, match="law: str"):
        @scenarios.register("_bad2", laws=("routh",), summary="x", help={})
        def bad2(law: str = "smith"):
            pass
    with pytest.raises(ValueError, match="unknown laws"):
        scenarios.register("_bad3", laws=("newton",), summary="x", help={})
    with pytest.raises(ValueError, match="already registered"):
        @scenarios.register("bouncing_ball", laws=("routh",), summary="x", help={})
        def dup(law: str = "routh"):
            pass
    assert scenarios.names() == tuple(sorted(NAMES + NAMES_3D + NAMES_MANY))


def test_import_is_light():
    code = ("import sys, rbimpact.scenarios as s; s.names(); "
            "bad = [m for m in ('pymunk', 'matplotlib', 'numba', 'rbimpact.scene', "
            "'rbimpact.simulation') if m in sys.modules]; print(bad)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.strip()
    assert out == "[]"


# ------------------------------------------------------------------ rbimpact list / run

def test_list_text():
    text = list_text()
    for name in NAMES:
        assert f"\n{name}: " in text
    assert "routh (default)" in text and "chatterjee_ruina (default)" in text
    assert "e=0.8" in text and "elastic=False" in text


def test_run_scenario_summary():
    text = run_scenario("bouncing_ball")
    lines = text.splitlines()
    assert lines[0].startswith("scenario: bouncing_ball")
    assert "law: routh (e=0.8, mu=0, restitution='energetic')" in text
    assert "status: done" in text
    assert any(x.startswith("events: ") and "impacts" in x and "contact 1" in x
               for x in lines)
    energy = next(x for x in lines if x.startswith("energy: start"))
    e0 = float(energy.split("start ")[1].split(" J")[0])
    assert e0 == pytest.approx(1.0 * 9.80665 * 1.05, rel=1e-5)
    assert "energy created: none (routh never creates energy)" in text
    assert "run time: " in text and " warm" in text
    err = float(text.split("max relative error ")[1].split(";")[0])
    assert err < 1e-10


def test_run_scenario_law_settings_and_outputs(tmp_path):
    out = tmp_path / "events.csv"
    text = run_scenario("falling_rod", law="kane_levinson", settings=["mu=0.2", "angle=0.4"],
                        t_end=1.0, out=str(out))
    assert "law: kane_levinson (e=0.8, mu=0.2)" in text
    assert "settings: mu=0.2, angle=0.4" in text
    assert "of 1 s" in text
    assert "kane_levinson may create energy" in text
    rows = list(csv.DictReader(open(out)))
    n = int(text.split("events: ")[1].split(" impact")[0])
    assert len(rows) == n and rows[0]["kind"] == "impact"
    js = tmp_path / "events.json"
    run_scenario("perforation", out=str(js))
    doc = json.load(open(js))
    assert doc["status"] == "done" and len(doc["events"]) == 1


def test_run_scenario_reports_energy_created_by_kane_levinson():
    # DESIGN §4: K&L's stick branch creates energy at e = 1 on a coupled contact (rod end)
    text = run_scenario("falling_rod", law="kane_levinson", settings=["e=1"])
    line = next(x for x in text.splitlines() if x.startswith("energy created"))
    assert "J in " in line and "(kane_levinson may create energy)" in line
    assert float(line.split("energy created: ")[1].split(" J")[0]) > 1e-3
    text = run_scenario("falling_rod", law="routh", settings=["e=1"])
    assert "energy created: none (routh never creates energy)" in text


def test_run_scenario_plot(tmp_path):
    pytest.importorskip("matplotlib")
    fig = tmp_path / "fig.png"
    text = run_scenario("superball", plot=str(fig), t_end=0.5)
    assert fig.stat().st_size > 1000 and "plot written" in text


@pytest.mark.parametrize("kw,match", [
    ({"law": "brach", "settings": ["e=-0.5"], "name": "bouncing_ball"}, None),
    ({"law": "newton"}, "supports the laws"),
    ({"settings": ["e=x"]}, "must be a float"),
    ({"t_end": -1.0}, "t_end must be a positive"),
    ({"name": "nope"}, "unknown scenario"),
])
def test_run_scenario_errors(kw, match):
    kw = dict(kw)
    name = kw.pop("name", "bouncing_ball")
    if match is None:  # Brach accepts e < 0: the ball goes through the floor
        text = run_scenario(name, t_end=1.0, **kw)
        assert "events: 1 impact," in text
        return
    with pytest.raises(ValueError, match=match):
        run_scenario(name, **kw)


def test_run_scenario_help():
    text = run_scenario("superball", settings=["help=1"])
    assert "e_t (float, default 0.95)" in text and "table (float" in text


def test_run_scenario_stepper_error_keeps_the_partial_summary():
    from rbimpact import SimulationError
    with pytest.raises(SimulationError) as info:
        # a rod landing flat under the simultaneous policy with Brach's e < 0: the joint
        # Newton solve needs 0 <= e <= 1 (the documented SimulationError)
        run_scenario("falling_rod", law="brach", settings=["e=-0.5", "angle=0.0"],
                     t_end=5.0)
    msg = str(info.value)
    assert "simultaneous policy needs 0 <= e <= 1" in msg
    assert info.value.result.status == "joint_e"
    assert "the run up to the error" in msg and "status: stopped by the error" in msg
    assert info.value.result is not None and info.value.result.t_end < 5.0


@pytest.mark.parametrize("law", scenarios.spec("box_stack").laws)
def test_box_stack_stays_where_it_was_placed(runs, law):
    """Issue 16: a stack of five boxes rests for 10 s, every law: no box moves by more than
    1e-15 m or turns (the 2.4e-9 s of free fall before the contacts accumulate: 3e-17 m)."""
    sc, r = runs("box_stack", law)
    s = r.sample(np.linspace(0.0, sc.t_end, 201))
    k = np.arange(5)
    assert np.abs(s["x"] - 0.02 * k).max() <= 1e-15
    assert np.abs(s["y"] - (0.1 + 0.2 * k)).max() <= 1e-15
    assert np.abs(s["angle"]).max() <= 1e-15
    assert "rest" in set(r.events["kind"])
