"""The benchmark functions on tiny sizes: structure, ratios consistent with the figures they
are computed from (same run), and the physical facts the figures rest on (a 2D scene
touches no 3D kernel; pymunk's fixed-step error against the exact run). No timing
thresholds: timings on a shared machine are not tested."""
import json
import math

import pytest

from rbimpact import bench


def _close(a, b, rtol=1e-9):
    return math.isclose(a, b, rel_tol=rtol)


def test_laws_rows_and_ratios_are_consistent():
    rows = bench.bench_laws(n=4000, repeat=1)
    copy = {r["dim"]: r for r in rows if r["item"].startswith("plain copy")}
    numpy_kl = next(r for r in rows if r["item"].startswith("NumPy"))
    assert set(copy) == {2, 3}
    laws = [r for r in rows if "vs_copy" in r and not r["item"].startswith("NumPy")]
    for name in bench.LAW_SETTINGS:
        for d in (2, 3):
            assert any(r["item"] == f"{name} {d}D" and r["threads"] == 1 for r in laws)
    for r in laws + [numpy_kl]:
        assert r["contacts_per_s"] > 0
        assert _close(r["vs_copy"], r["contacts_per_s"] / copy[r["dim"]]["contacts_per_s"])
        if r["dim"] == 2:
            assert _close(r["vs_numpy_kl2d"], r["contacts_per_s"] / numpy_kl["contacts_per_s"])


def test_overhead_ratio_is_resolve_over_kernel():
    rows = bench.bench_overhead(repeat=1, n=500, laws=("kane_levinson",))
    assert [r["item"] for r in rows] == ["kane_levinson"]
    for r in rows:
        assert r["resolve_us"] > 0 and r["njit_kernel_ns"] > 0
        assert _close(r["ratio"], 1e3 * r["resolve_us"] / r["njit_kernel_ns"])


def test_stepper_rows_count_the_impacts_they_time():
    rows = bench.bench_stepper(repeat=1, n_elastic=300, tosses=2, with_3d=True)
    elastic = rows[0]
    assert elastic["impacts"] == 300           # the elastic ball stops at max_events impacts
    assert _close(elastic["vs_target"], elastic["impacts_per_s"] / bench.STEPPER_TARGET)
    assert _close(elastic["per_impact_vs_elastic"], 1.0)
    per_impact = elastic["run_s"] / elastic["impacts"]
    by_item = {r["item"]: r for r in rows}
    # the e = 0.8 ball: impacts until the accumulation point (geometric series, DESIGN §6)
    assert by_item["bouncing_ball e=0.8 to rest"]["impacts"] == 52
    for r in rows:
        if "run_s" in r and r["impacts"]:
            assert _close(r["per_impact_vs_elastic"], r["run_s"] / r["impacts"] / per_impact)
            assert _close(r["impacts_per_s"], r["impacts"] / r["run_s"])
    fixed = by_item["fixed cost of run() (no event)"]
    assert fixed["events"] == 0 and _close(fixed["per_impact_vs_elastic"],
                                           fixed["run_s"] / per_impact)
    die = [r for r in rows if r["item"].startswith("die_toss")]
    assert len(die) == 3 and all(r["impacts"] > 0 for r in die[:2])
    batch = die[-1]
    assert batch["unresolved"] + sum(batch["faces"]) == 2 and batch["impacts_per_s"] > 0
    assert _close(batch["per_impact_vs_elastic"], 1.0 / batch["impacts_per_s"] / per_impact)


def test_pay_only_for_what_is_used_a_2d_scene_touches_no_3d_kernel():
    rows = bench.bench_pay(repeat=1, cold=False)
    assert len(rows) == 2
    one, full = rows
    for r in rows:
        assert r["compiled_3d_kernels"] == 0 and r["modules_3d_imported"] == 0
        assert _close(r["per_impact_vs_full"], r["per_impact_s"] / full["per_impact_s"])
        assert _close(r["first_run_vs_full"], r["first_run_s"] / full["first_run_s"])
    assert one["impacts"] == 52 and full["impacts"] > 0


def test_pymunk_ratios_and_its_first_order_error():
    pytest.importorskip("pymunk")
    rows = bench.bench_pymunk(repeat=1, dts=(1e-2, 1e-3))
    exact = next(r for r in rows if r["engine"] == "rbimpact")
    assert exact["time_ratio"] == 1.0 and exact["error_m"] < 1e-12
    pm = sorted((r for r in rows if r["engine"] == "pymunk"), key=lambda r: r["dt_s"])
    for r in pm:
        assert _close(r["time_ratio"], r["run_time_s"] / exact["run_time_s"])
        assert _close(r["error_ratio"], r["error_m"] / exact["error_m"])
        assert r["error_ratio"] > 1e6           # a fixed step against the exact run
    # first order: ten times the step, about ten times the error (not second order)
    assert 3.0 < pm[1]["error_m"] / pm[0]["error_m"] < 30.0


def test_rotation3d_json_carries_every_figure(tmp_path, capsys):
    path = tmp_path / "bench.json"
    assert bench.main("rotation3d", repeat=2, json_path=str(path)) == 0
    data = json.loads(path.read_text())
    assert list(data) == ["rotation3d"]
    rows = data["rotation3d"]
    ladder = [r for r in rows if r["rot_tol"] > 0]
    from rbimpact import bench3d
    assert [r["rot_tol"] for r in ladder] == list(bench3d.ROT_TOLS)
    for r in ladder:
        assert _close(r["error_over_tol"], r["orientation_error_rad"] / r["rot_tol"])
    # the integrator converges: the tightest tolerance is far more accurate than the loosest
    assert ladder[-1]["orientation_error_rad"] < 1e-4 * ladder[0]["orientation_error_rad"]
    assert "rot_tol" in capsys.readouterr().out


def test_bench_subcommands_cover_every_section():
    covered = {k for keys in bench.WHAT.values() for k in keys}
    assert covered == set(bench.SECTIONS) and bench.WHAT["all"] == bench.SECTIONS
    with pytest.raises(ValueError, match="what must be one of"):
        bench.main("nothing")
