"""Exports of a run's events: the vectorized CSV against the former row-by-row writer,
to_pandas / to_parquet, the optional-dependency messages, and what ``import rbimpact`` loads."""
import subprocess
import sys

import numpy as np
import pytest

from rbimpact import scenarios


def reference_csv(res, path):
    """The CSV writer as it was before it was vectorized (csv.writer, repr of floats): the
    row-by-row reference that ``rbimpact bench sweep`` also times."""
    from rbimpact.bench import _csv_rowwise
    _csv_rowwise(res, path)


@pytest.fixture(scope="module")
def run2d():
    return scenarios.get("spinning_ball").simulate()


@pytest.fixture(scope="module")
def run3d():
    return scenarios.get("die_toss", seed=1).simulate()


@pytest.mark.parametrize("which", ["run2d", "run3d"])
def test_csv_is_byte_identical_to_the_former_writer(which, request, tmp_path):
    res = request.getfixturevalue(which)
    assert len(res.events) > 20 and len(set(res.events["kind"])) >= 2
    reference_csv(res, tmp_path / "old.csv")
    res.to_csv(tmp_path / "new.csv")
    assert (tmp_path / "new.csv").read_bytes() == (tmp_path / "old.csv").read_bytes()


def test_csv_floats_are_repr_for_every_kind_of_double(run2d, tmp_path):
    # random bit patterns (subnormals, huge, tiny, nan, inf), decimals, integers, signed zeros
    rng = np.random.default_rng(17)
    n = 4000
    ev = np.empty(n, dtype=run2d.events.dtype)
    bits = rng.integers(0, 2 ** 63, (n, 13), dtype=np.int64).astype(np.uint64)
    bits |= rng.integers(0, 2, (n, 13)).astype(np.uint64) << np.uint64(63)
    F = bits.view(np.float64)
    F[:500] = np.round(rng.normal(size=(500, 13)) * 10.0 ** rng.integers(-6, 18, (500, 13)),
                       3)
    F[500:600] = rng.integers(-10 ** 6, 10 ** 6, (100, 13))
    special = [0.0, -0.0, 1.0, 0.1, 1e16, 1e15, 9999999999999998.0, 1e-4, 1e-5, 5e-324,
               2.2250738585072014e-308, 1.7976931348623157e308, np.inf, -np.inf, np.nan,
               1e22, 1e23, 2.0 ** 63, 1 / 3, 100.0, 0.3 - 0.1, -1.5e-7, 123456789.0]
    F[600:600 + len(special)] = np.array(special)[:, None]
    F[700:800] = F[699]                  # repeated rows: the copy-the-row-above path
    ev["t"], ev["dE"] = F[:, 0], F[:, 1]
    for k, name in enumerate(run2d._EVENT_VECTORS):
        ev[name] = F[:, 2 + 2 * k:4 + 2 * k]
    ev["kind"] = rng.choice(["impact", "contact", "release", "rest"], n)
    ev["a"] = rng.integers(-5, 10 ** 12, n)
    ev["b"] = -1
    ev["mode"] = rng.integers(-2, 5, n)
    ev["cluster"] = 1
    fake = type(run2d).__new__(type(run2d))
    fake.__dict__.update(run2d.__dict__)
    fake._events = ev
    reference_csv(fake, tmp_path / "old.csv")
    fake.to_csv(tmp_path / "new.csv")
    assert (tmp_path / "new.csv").read_bytes() == (tmp_path / "old.csv").read_bytes()
    fake._events = ev[:0]
    fake.to_csv(tmp_path / "empty.csv")
    assert (tmp_path / "empty.csv").read_text() == ",".join(run2d.FIELDS_CSV) + "\n"
    assert len(fake.to_pandas()) == 0


@pytest.mark.parametrize("which", ["run2d", "run3d"])
def test_to_pandas_columns_and_values_match_events(which, request):
    pytest.importorskip("pandas")
    res = request.getfixturevalue(which)
    ev = res.events
    df = res.to_pandas()
    assert tuple(df.columns) == res.FIELDS_CSV and len(df) == len(ev)
    d = 2 if which == "run2d" else 3
    tang = ("T",) if d == 2 else ("T1", "T2")
    for vec in ("v_i", "v_f", "P"):
        for k, c in enumerate(("N",) + tang):
            np.testing.assert_array_equal(df[f"{vec}_{c}"].to_numpy(), ev[vec][:, k])
    for k, c in enumerate("xyz"[:d]):
        np.testing.assert_array_equal(df[f"point_{c}"].to_numpy(), ev["point"][:, k])
        np.testing.assert_array_equal(df[f"normal_{c}"].to_numpy(), ev["normal"][:, k])
    for name in ("t", "a", "b", "mode", "dE", "cluster"):
        np.testing.assert_array_equal(df[name].to_numpy(), ev[name])
    assert df["kind"].astype(str).tolist() == ev["kind"].tolist()
    assert df.attrs["status"] == res.status and df.attrs["t_end"] == res.t_end


def test_to_parquet_round_trips(run3d, tmp_path):
    pd = pytest.importorskip("pandas")
    pytest.importorskip("pyarrow")
    run3d.to_parquet(tmp_path / "ev.parquet")
    back = pd.read_parquet(tmp_path / "ev.parquet")
    pd.testing.assert_frame_equal(back, run3d.to_pandas(), check_categorical=False)


def test_missing_pandas_names_the_extra(run2d, monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)     # import pandas -> ImportError
    with pytest.raises(ImportError, match=r"Result.to_pandas needs pandas: pip install "
                                          r"'rbimpact\[sweep\]'"):
        run2d.to_pandas()
    monkeypatch.setitem(sys.modules, "pyarrow", None)
    with pytest.raises(ImportError, match=r"needs pyarrow: pip install 'rbimpact\[sweep\]'"):
        run2d.to_parquet("never.parquet")


def test_import_rbimpact_loads_no_optional_package():
    code = ("import sys, rbimpact, rbimpact.progress; rbimpact.sweep; "
            "from rbimpact import result, result3d; "
            "bad = [m for m in ('pandas', 'dask', 'distributed', 'tqdm', 'pyarrow') "
            "if m in sys.modules]; print(bad)")
    out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True,
                         text=True).stdout.strip()
    assert out == "[]"
