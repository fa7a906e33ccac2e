"""rbimpact.sweep: a small sweep on a Dask LocalCluster equals the in-process one, resuming
skips finished runs (also after a kill), failed runs are rows, bad input is a one-line
ValueError before anything runs; the command line; progress bars."""
import io
import os

import pytest

pd = pytest.importorskip("pandas")
pytest.importorskip("pyarrow")

import rbimpact  # noqa: E402
import rbimpact.sweep as sweep_mod  # noqa: E402
from rbimpact.cli import main  # noqa: E402
from rbimpact.progress import progress  # noqa: E402

GRID = {"mu": [0.2, 0.5], "e": [0.3, 0.6]}


@pytest.fixture(scope="module")
def table():
    return rbimpact.sweep("die_toss", grid=GRID, seeds=2, workers=1, progress=False)


def test_table_layout_and_values(table):
    assert len(table) == 8 and table.attrs["ran"] == 8
    assert list(table.columns[:6]) == ["scenario", "law", "mu", "e", "seed", "status"]
    assert {"impacts", "energy_lost", "x_final", "y_final", "z_final", "face",
            "run_s"} <= set(table.columns)
    assert (table["status"] == "done").all() and (table["error"] == "").all()
    assert table["face"].between(1, 6).all() and (table["impacts"] > 0).all()
    # sorted by law, grid values, seed
    assert table[["mu", "e", "seed"]].values.tolist() == sorted(
        table[["mu", "e", "seed"]].values.tolist())
    # a row is the scenario run directly with those parameters
    from rbimpact import scenarios
    from rbimpact.scenarios.die_toss import face_up
    row = table.iloc[5]
    r = scenarios.get("die_toss", mu=row.mu, e=row.e, seed=int(row.seed)).simulate()
    assert row.impacts == r.n_impacts and row.face == face_up(r)
    e = r.energy([0.0, r.t_end])
    assert row.energy_lost == e[0] - e[1]


def test_local_cluster_gives_the_same_table(table):
    pytest.importorskip("distributed")
    df = rbimpact.sweep("die_toss", grid=GRID, seeds=2, workers=2, progress=False)
    assert df.attrs["workers"] == 2
    pd.testing.assert_frame_equal(df.drop(columns="run_s"), table.drop(columns="run_s"))


def test_resume_skips_finished_runs(tmp_path, table, monkeypatch):
    out = tmp_path / "t.parquet"
    first = rbimpact.sweep("die_toss", grid=GRID, seeds=1, out=out, progress=False)
    assert first.attrs["ran"] == 4 and out.exists()
    assert not os.path.exists(str(out) + ".partial.jsonl")
    # a sweep killed before it consolidates leaves its finished runs in the sidecar
    real = sweep_mod.run_one
    calls = []

    def counting(scenario, keys, run):
        calls.append(run)
        if len(calls) == 1 + 3:          # warm-up run, then the third run of the sweep
            raise KeyboardInterrupt
        return real(scenario, keys, run)

    monkeypatch.setattr(sweep_mod, "run_one", counting)
    monkeypatch.setattr(sweep_mod._Store, "consolidate", lambda self, df: None)
    with pytest.raises(KeyboardInterrupt):
        rbimpact.sweep("die_toss", grid=GRID, seeds=2, out=out, progress=False)
    side = str(out) + ".partial.jsonl"
    with open(side, "a") as f:
        f.write('{"scenario": "die_toss", "law": "chatter')   # a line cut by the kill
    assert len(open(side).read().splitlines()) == 3
    monkeypatch.undo()
    df = rbimpact.sweep("die_toss", grid=GRID, seeds=2, out=out, progress=False)
    assert df.attrs["skipped"] == 4 + 2 and df.attrs["ran"] == 2
    assert not os.path.exists(side)
    pd.testing.assert_frame_equal(df.drop(columns="run_s"), table.drop(columns="run_s"))
    back = pd.read_parquet(out)
    assert len(back) == 8
    # the rows of the first sweep were kept, not recomputed
    merged = df.merge(first, on=["law", "mu", "e", "seed"], suffixes=("", "_1"))
    assert len(merged) == 4 and (merged["run_s"] == merged["run_s_1"]).all()
    again = rbimpact.sweep("die_toss", grid=GRID, seeds=2, out=out, progress=False)
    assert again.attrs["ran"] == 0
    with pytest.raises(ValueError, match="holds another sweep"):
        rbimpact.sweep("die_toss", grid={"spin": [10.0]}, out=out, progress=False)


def test_a_distributed_sweep_killed_keeps_its_finished_runs(tmp_path, table, monkeypatch):
    pytest.importorskip("distributed")
    out = tmp_path / "k.parquet"
    real = sweep_mod._Store.append
    seen = []

    def killed(self, row):                  # Ctrl-C after the third row arrived
        real(self, row)
        seen.append(row)
        if len(seen) == 3:
            raise KeyboardInterrupt

    monkeypatch.setattr(sweep_mod._Store, "append", killed)
    monkeypatch.setattr(sweep_mod._Store, "consolidate", lambda self, df: None)
    monkeypatch.setattr(sweep_mod, "TASKS_PER_WORKER", 4)     # chunks of one run
    with pytest.raises(KeyboardInterrupt):
        rbimpact.sweep("die_toss", grid=GRID, seeds=2, workers=2, out=out, progress=False)
    monkeypatch.undo()
    side = str(out) + ".partial.jsonl"
    assert len(open(side).read().splitlines()) == 3
    df = rbimpact.sweep("die_toss", grid=GRID, seeds=2, workers=2, out=out, progress=False)
    assert df.attrs["skipped"] == 3 and df.attrs["ran"] == 5
    pd.testing.assert_frame_equal(df.drop(columns="run_s"), table.drop(columns="run_s"))


def test_a_failed_run_is_a_row(monkeypatch):
    real = sweep_mod._summary

    def flaky(scenario, result):
        if result.n_impacts % 2:
            raise RuntimeError("boom\nsecond line")
        return real(scenario, result)

    monkeypatch.setattr(sweep_mod, "_summary", flaky)
    df = rbimpact.sweep("die_toss", seeds=6, progress=False)
    bad = df[df["status"] == "error"]
    assert len(df) == 6 and 0 < len(bad) < 6
    assert (bad["error"] == "RuntimeError: boom").all() and bad["impacts"].isna().all()


@pytest.mark.parametrize("kw, match", [
    (dict(grid={"foo": [1.0]}), r"scenario 'die_toss' has no parameter 'foo'; its "
                                r"parameters are e, mu"),
    (dict(grid={"mu": [0.2, -1.0]}), r"mu=-1.0, .*'mu' must be finite and in \[0, inf\)"),
    (dict(grid={"height": [0.001]}), r"height must be > size sqrt\(3\)/2"),
    (dict(grid={"mu": ["x"]}), r"'mu' must be a float, got 'x'"),
    (dict(grid={"seed": [1, 2]}), r"'seed' is not a grid key: use the seeds argument"),
    (dict(law="newton"), r"supports the laws kane_levinson, .*got law='newton'"),
    (dict(seeds=0), r"seeds must be >= 1"),
    (dict(workers=0), r"workers must be a positive int"),
])
def test_bad_input_is_one_line_before_anything_runs(kw, match, tmp_path, monkeypatch):
    monkeypatch.setattr(sweep_mod, "run_one", None)           # nothing may run
    out = tmp_path / "never.parquet"
    with pytest.raises(ValueError, match=match) as info:
        rbimpact.sweep("die_toss", out=out, **kw)
    assert "\n" not in str(info.value) and not out.exists()
    with pytest.raises(ValueError, match="no seed parameter .* use seeds=1"):
        rbimpact.sweep("bouncing_ball", seeds=3)
    with pytest.raises(ValueError, match="unknown scenario 'nope'"):
        rbimpact.sweep("nope")


def test_command_line(tmp_path, capsys):
    out = tmp_path / "r.parquet"
    assert main(["sweep", "bouncing_ball", "--grid", "e=0.5,0.8", "--grid", "h=1,2",
                 "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert text.startswith("sweep bouncing_ball: 4 runs, 4 computed in ")
    assert "status: done 4" in text and f"table written to {out}" in text
    df = pd.read_parquet(out)
    assert df[["e", "h"]].values.tolist() == [[0.5, 1.0], [0.5, 2.0], [0.8, 1.0], [0.8, 2.0]]
    assert (df["impacts"] > 10).all() and df["y_final"].to_numpy() == pytest.approx(0.05)
    for argv, msg in [
        (["--grid", "foo=1"], "scenario 'bouncing_ball' has no parameter 'foo'"),
        (["--grid", "e=2"], "'e' must be finite and in [0, 1]"),
        (["--grid", "e"], "--grid 'e' is not of the form KEY=V1,V2,..."),
        (["--seeds", "3"], "scenario 'bouncing_ball' has no seed parameter"),
        (["--out", str(tmp_path / "r.csv")], "out must be a .parquet file"),
    ]:
        assert main(["sweep", "bouncing_ball", *argv]) == 2
        err = capsys.readouterr().err
        assert err.startswith("rbimpact sweep: error: ") and msg in err, err
        assert err.count("\n") == 1


def test_sweep_is_callable_after_importing_the_module():
    assert callable(rbimpact.sweep) and callable(sweep_mod)
    df = sweep_mod("bouncing_ball", grid={"h": [0.5]}, progress=False)
    assert len(df) == 1 and df["status"][0] == "done"


def test_progress_is_silent_off_a_terminal(monkeypatch):
    items = [1, 2, 3]
    monkeypatch.delenv("RBIMPACT_PROGRESS", raising=False)
    assert progress(items, desc="x", stream=io.StringIO()) is items
    tqdm = pytest.importorskip("tqdm")
    monkeypatch.setenv("RBIMPACT_PROGRESS", "1")
    buf = io.StringIO()
    bar = progress(items, desc="x", stream=buf)
    assert isinstance(bar, tqdm.tqdm) and list(bar) == items and "3/3" in buf.getvalue()
    monkeypatch.setenv("RBIMPACT_PROGRESS", "0")
    assert progress(items, stream=buf) is items


def test_bench_sweep_rows():
    from rbimpact.bench import _print_sweep, bench_sweep
    rows = bench_sweep(seeds=6, workers=(1,), csv_events=3000, old_events=500, tosses=4,
                       pairs=1)
    assert rows[0]["identical_table"] and rows[0]["speedup"] == 1.0
    assert rows[0]["compute_s"] > 0 and rows[0]["errors"] == 0
    assert rows[-1]["same_bytes"] and rows[-1]["new_s_per_1e6"] > 0
    _print_sweep(rows)
