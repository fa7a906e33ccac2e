"""The command line's failure modes (issue 13, item 7): bad arguments and unwritable output
files give one line on stderr and exit status 2 (the run's summary still printed when the
failure comes after it), Ctrl-C gives one line and 130, never a traceback."""
import importlib
import os
import signal
import subprocess
import sys
import time

import pytest

from rbimpact import cli
import rbimpact._validate as validate
from rbimpact._validate import writable_path


def _one_error_line(err, where, *words):
    lines = [x for x in err.splitlines() if x.strip()]
    assert len(lines) == 1, err
    assert lines[0].startswith(f"rbimpact {where}: error: "), err
    for w in words:
        assert w in lines[0], (w, err)
    assert "Traceback" not in err


@pytest.fixture
def no_precheck(monkeypatch):
    """Let an unwritable path through the check made before the run, so that the write
    after the run fails (as when a disk fills up or a directory goes away meanwhile)."""
    monkeypatch.setattr(validate, "writable_path", lambda what, path: path)


# ---------------------------------------------------------------- bad arguments

def test_laws_runs():
    assert cli.main(["laws"]) == 0


@pytest.mark.parametrize("argv, words", [
    (["laws", "--e", "2"], ["parameter 'e'", "[0, 1]"]),
    (["laws", "--e", "nan"], ["finite"]),
    (["laws", "--v", "1", "2", "3", "4"], ["--v takes 2"]),
    (["laws", "--v", "1e155", "0"], ["energy is not representable"]),
    (["run", "bouncing_ball", "--t-end", "-1"], ["t_end must be a positive"]),
    (["run", "bouncing_ball", "--set", "e=abc"], ["must be a float"]),
    (["run", "no_such_scenario"], ["unknown scenario"]),
])
def test_bad_arguments_give_one_line_and_status_2(capsys, argv, words):
    assert cli.main(argv) == 2
    _one_error_line(capsys.readouterr().err, argv[0], *words)


def test_a_type_error_is_one_line_too(capsys, monkeypatch):
    import rbimpact.run

    def bad(*a, **k):
        raise TypeError("add_body() got an unexpected keyword\nargument 'speed'")
    monkeypatch.setattr(rbimpact.run, "run_scenario", bad)
    assert cli.main(["run", "bouncing_ball"]) == 2
    _one_error_line(capsys.readouterr().err, "run", "unexpected keyword argument 'speed'")


@pytest.mark.parametrize("argv", [["bench", "--repeat", "0"], ["bench", "--repeat", "-2"],
                                  ["bench", "laws", "--repeat", "x"],
                                  ["crosscheck", "bouncing_ball", "--repeat", "0"],
                                  ["impulse-space", "--n", "0"]])
def test_counts_must_be_positive_integers(capsys, argv):
    with pytest.raises(SystemExit) as info:
        cli.main(argv)
    assert info.value.code == 2
    err = capsys.readouterr().err
    assert "must be a positive integer" in err and "Traceback" not in err


# ---------------------------------------------------------------- output files: before the run

@pytest.mark.parametrize("opt", ["--out", "--plot"])
def test_run_refuses_an_unwritable_path_before_running(capsys, monkeypatch, tmp_path, opt):
    import rbimpact.run
    monkeypatch.setattr(rbimpact.run, "run_scenario",
                        lambda *a, **k: pytest.fail("ran before checking the output path"))
    for path, words in ((tmp_path / "missing" / "x.csv", "does not exist"),
                        (tmp_path, "is a directory")):
        assert cli.main(["run", "bouncing_ball", opt, str(path)]) == 2
        out, err = capsys.readouterr()
        assert out == ""
        _one_error_line(err, "run", opt, "cannot write", words)


@pytest.mark.parametrize("argv", [["crosscheck", "bouncing_ball", "--out"],
                                  ["crosscheck", "bouncing_ball", "--plot"],
                                  ["bench", "laws", "--json"], ["stability", "--out"],
                                  ["impulse-space", "--plot"],
                                  ["sweep", "bouncing_ball", "--out"]])
def test_every_output_option_is_checked_before_the_command(capsys, monkeypatch, tmp_path, argv):
    for mod, fn in (("crosscheck", "crosscheck_report"), ("bench", "main"),
                    ("stability", "stability_report"),
                    ("impulse_region", "impulse_space_report"), ("sweep", "sweep_command")):
        monkeypatch.setattr(importlib.import_module(f"rbimpact.{mod}"), fn,
                            lambda *a, **k: pytest.fail("ran before checking the path"))
    assert cli.main(argv + [str(tmp_path / "nope" / "f.parquet")]) == 2
    _one_error_line(capsys.readouterr().err, argv[0], argv[-1], "does not exist")


def test_writable_path_reasons(tmp_path, monkeypatch):
    f = tmp_path / "a.csv"
    assert writable_path("--out", str(f)) == str(f)
    f.write_text("x")
    assert writable_path("--out", f) == f                      # an existing file, overwritten
    for bad, why in ((tmp_path / "no" / "a.csv", "does not exist"),
                     (tmp_path, "is a directory"), (f / "b.csv", "is not a directory"),
                     ("", "empty")):
        with pytest.raises(ValueError, match=why):
            writable_path("--out", bad)
    monkeypatch.setattr(os, "access", lambda *a, **k: False)   # as for a non-root user
    with pytest.raises(ValueError, match="no permission to write the file"):
        writable_path("--out", f)
    with pytest.raises(ValueError, match="no permission to create files"):
        writable_path("--out", tmp_path / "new.csv")


@pytest.mark.skipif(hasattr(os, "geteuid") and os.geteuid() == 0,
                    reason="root may write anywhere")
def test_run_refuses_a_directory_without_write_permission(capsys, tmp_path):
    d = tmp_path / "ro"
    d.mkdir()
    d.chmod(0o500)
    try:
        assert cli.main(["run", "bouncing_ball", "--out", str(d / "x.csv")]) == 2
        _one_error_line(capsys.readouterr().err, "run", "no permission")
    finally:
        d.chmod(0o700)


# ---------------------------------------------------------------- output files: after the run

def test_run_prints_its_summary_when_a_write_fails_after_the_run(capsys, no_precheck, tmp_path):
    fig = tmp_path / "fig.png"
    status = cli.main(["run", "bouncing_ball", "--t-end", "0.5",
                       "--out", str(tmp_path / "gone" / "events.csv"), "--plot", str(fig)])
    out, err = capsys.readouterr()
    assert status == 2
    assert "scenario: bouncing_ball" in out and "events: 1 impact" in out
    assert f"plot written to {fig}" in out and fig.stat().st_size > 1000   # the other file
    _one_error_line(err, "run", "could not write --out", "events.csv")


def test_run_scenario_raises_output_error_with_the_summary(no_precheck, tmp_path):
    from rbimpact.errors import OutputError
    from rbimpact.run import run_scenario
    bad = str(tmp_path / "gone" / "e.json")
    with pytest.raises(OutputError) as info:
        run_scenario("bouncing_ball", t_end=0.5, out=bad)
    assert isinstance(info.value, OSError)
    assert "scenario: bouncing_ball" in info.value.summary and info.value.paths == (bad,)
    assert "could not write out" in str(info.value)


def test_run_scenario_checks_its_paths_before_running(tmp_path):
    from rbimpact.run import run_scenario
    with pytest.raises(ValueError, match="plot: cannot write .* is a directory"):
        run_scenario("bouncing_ball", t_end=0.5, plot=str(tmp_path))


def test_crosscheck_prints_its_table_when_a_write_fails(capsys, no_precheck, tmp_path):
    png, csv = tmp_path / "wp.png", tmp_path / "gone" / "t.csv"
    status = cli.main(["crosscheck", "bouncing_ball", "--dt", "1e-2", "--repeat", "1",
                       "--out", str(csv), "--plot", str(png)])
    out, err = capsys.readouterr()
    assert status == 2
    assert "crosscheck bouncing_ball" in out and "rbimpact" in out
    assert f"plot written to {png}" in out and png.stat().st_size > 1000
    _one_error_line(err, "crosscheck", "could not write --out", "t.csv")
    # and a writable --out is written as before
    good = tmp_path / "t.csv"
    assert cli.main(["crosscheck", "bouncing_ball", "--dt", "1e-2", "--repeat", "1",
                     "--out", str(good)]) == 0
    assert good.read_text().startswith("scenario,law,engine") and \
        f"table written to {good}" in capsys.readouterr().out


def test_bench_json_failure_after_the_figures(capsys, no_precheck, monkeypatch, tmp_path):
    import rbimpact.bench as bench

    def fake_main(what, repeat, json_path):
        print("figures of", what)
        with open(json_path, "w"):
            pass
    monkeypatch.setattr(bench, "main", fake_main)
    bad = str(tmp_path / "gone" / "b.json")
    assert cli.main(["bench", "laws", "--json", bad]) == 2
    out, err = capsys.readouterr()
    assert "figures of laws" in out
    _one_error_line(err, "bench", "could not write --json", "b.json")


def test_stability_table_printed_when_its_csv_fails(capsys, no_precheck, monkeypatch, tmp_path):
    import rbimpact.stability as stability
    monkeypatch.setattr(stability, "stability_report", lambda quick=False: ("the table", [], True))
    assert cli.main(["stability", "--out", str(tmp_path / "gone" / "s.csv")]) == 2
    out, err = capsys.readouterr()
    assert "the table" in out
    _one_error_line(err, "stability", "could not write --out")
    good = tmp_path / "s.csv"
    assert cli.main(["stability", "--out", str(good)]) == 0 and good.exists()


# ---------------------------------------------------------------- Ctrl-C

def test_keyboard_interrupt_is_one_line_and_status_130(capsys, monkeypatch):
    import rbimpact.run

    def interrupted(*a, **k):
        raise KeyboardInterrupt
    monkeypatch.setattr(rbimpact.run, "run_scenario", interrupted)
    assert cli.main(["run", "bouncing_ball"]) == 130
    err = capsys.readouterr().err
    assert err.strip() == "rbimpact run: interrupted (Ctrl-C)"


def test_ctrl_c_in_a_real_process(tmp_path):
    """SIGINT to a running ``rbimpact run``: one line on stderr, status 130."""
    # a child started from a non-interactive shell's background job inherits SIGINT ignored;
    # a user's terminal delivers it: restore Python's handler as an interactive start has it
    code = ("import signal, sys, time, rbimpact.run, rbimpact.cli\n"
            "signal.signal(signal.SIGINT, signal.default_int_handler)\n"
            "def slow(*a, **k):\n"
            "    print('running', flush=True)\n"
            "    time.sleep(60)\n"
            "rbimpact.run.run_scenario = slow\n"
            "sys.exit(rbimpact.cli.main(['run', 'bouncing_ball']))\n")
    proc = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    try:
        assert proc.stdout.readline().strip() == "running"
        time.sleep(0.2)
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=120)   # generous: shared CI machines
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130
    assert err.strip() == "rbimpact run: interrupted (Ctrl-C)", err


@pytest.mark.parametrize("repeat", [0, -1, 2.5, True, "3"])
def test_bench_main_refuses_a_repeat_below_one(repeat):
    import rbimpact.bench as bench
    with pytest.raises(ValueError, match="bench: repeat must be an integer in \\[1, "):
        bench.main("laws", repeat=repeat)


def test_impulse_space_prints_its_summary_when_the_plot_fails(capsys, no_precheck, tmp_path):
    assert cli.main(["impulse-space", "--n", "20", "--plot",
                     str(tmp_path / "gone" / "r.png")]) == 2
    out, err = capsys.readouterr()
    assert "Impulse space of one contact" in out and "Kane & Levinson" in out
    _one_error_line(err, "impulse-space", "could not write --plot", "r.png")
    good = tmp_path / "r.png"
    assert cli.main(["impulse-space", "--n", "20", "--plot", str(good)]) == 0
    assert good.stat().st_size > 1000 and f"plot written to {good}" in capsys.readouterr().out


def test_a_closed_output_pipe_ends_quietly(capsys, monkeypatch):
    class ClosedPipe:
        def write(self, text):
            raise BrokenPipeError(32, "Broken pipe")

        def flush(self):
            pass
    monkeypatch.setattr(sys, "stdout", ClosedPipe())
    assert cli.main(["list"]) == 141
    assert capsys.readouterr().err == ""
