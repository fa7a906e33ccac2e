"""The logic of ``rbimpact list`` and ``rbimpact run`` (the argparse wiring is in cli.py).

``list_text()`` describes the scenario library; ``run_scenario(name, ...)`` builds a
scenario, runs it with the event-driven stepper and returns the printed summary: impacts
and other events, energy at start and end, energy created (if any, and whether the law
may create it), run time (warm, and the compile time of the first call), status, and the
error against the scenario's exact reference where it has one.
"""
import math
import time

import numpy as np

#: an impact "creates energy" when dE > ENERGY_GAIN_RTOL * sum |P| (|v_i| + |v_f|) / 2 (J),
#: the scale of the dot product that defines dE (its round-off is about 1e-16 of it).
ENERGY_GAIN_RTOL = 1e-12
#: ... and dE > ENERGY_GAIN_EFLOOR * (|E(0)| + |E(t_end)|) (J): below that a gain is round-off
#: of the scene's energy (e.g. 1e-45 J from contact velocities of 1e-31 m/s at rest)
ENERGY_GAIN_EFLOOR = 1e-15
#: a first (cold) run longer than this (s) is not repeated to time a warm run.
REPEAT_LIMIT = 10.0


def list_text():
    """Text of ``rbimpact list``: every scenario, its laws and its parameters."""
    from . import scenarios
    lines = ["Scenarios (rbimpact run NAME [--law LAW] [--set key=value ...] [--t-end T] "
             "[--out events.csv] [--plot fig.png]):", ""]
    for name in scenarios.names():
        s = scenarios.spec(name)
        laws = [f"{x} (default)" if x == s.default_law else x for x in s.laws]
        params = [f"{k}={p.default!r}" if p.type is str else f"{k}={p.default}"
                  for k, p in s.params.items() if k != "law"]
        lines.append(f"{name}: {s.summary}")
        lines.append(f"    laws: {', '.join(laws)}")
        lines.append(_wrap("    parameters: ", params))
        lines.append("")
    lines.append("Types, units and ranges of a scenario's parameters: "
                 "rbimpact run NAME --set help=1")
    return "\n".join(lines)


def _wrap(head, items, width=88):
    out, line = [], head
    for k, item in enumerate(items):
        piece = item + (", " if k < len(items) - 1 else "")
        if len(line) + len(piece) > width and line.strip():
            out.append(line.rstrip())
            line = " " * len(head)
        line += piece
    out.append(line.rstrip())
    return "\n".join(out)


def _timed_run(scenario, t_end):
    """Run twice when the first run is short: (result, warm s, cold s or None)."""
    t0 = time.perf_counter()
    result = scenario.simulate(t_end=t_end)
    cold = time.perf_counter() - t0
    if cold > REPEAT_LIMIT:
        return result, cold, None
    t0 = time.perf_counter()
    result = scenario.simulate(t_end=t_end)
    warm = time.perf_counter() - t0
    return result, warm, cold


def _fmt_time(s):
    if s < 1e-3:
        return f"{s * 1e6:.0f} us"
    if s < 1.0:
        return f"{s * 1e3:.2f} ms"
    return f"{s:.2f} s"


def _reference_lines(scenario, events, result=None):
    """Compare the run with the scenario's exact reference, if it has one."""
    ref = scenario.reference
    if ref is None:
        return []
    if hasattr(ref, "report_result") and result is not None:
        return ref.report_result(result)    # a reference that reads the whole run
    if hasattr(ref, "report"):
        return ref.report(events)           # a reference that compares itself
    impacts = events[events["kind"] == "impact"]
    if hasattr(ref, "impact_times"):
        n = min(30, len(impacts))
        if n == 0:
            return ["reference: no impact to compare"]
        exact = ref.impact_times(n)
        err = np.max(np.abs(impacts["t"][:n] - exact) / exact)
        t_inf = ref.t_inf
        extra = (f"; impacts accumulate at t_inf = {t_inf:.9f} s" if math.isfinite(t_inf)
                 else "")
        return [f"reference: first {n} impact times, max relative error {err:.1e}{extra}"]
    if hasattr(ref, "t1"):
        if len(impacts) == 0:
            return [f"reference: first impact at t = {ref.t1:.9f} s, but none happened"]
        err = abs(impacts["t"][0] - ref.t1) / ref.t1
        return [f"reference: first impact at t = {ref.t1:.9f} s, relative error {err:.1e}"]
    return []


def run_scenario(name, law=None, settings=(), t_end=None, out=None, plot=None):
    """Build scenario ``name``, run it and return the summary text (``rbimpact run``).

    ``law``: a law name replacing the scenario's default (keeping e, mu and the other
    parameters it takes); ``settings``: ``key=value`` strings (``--set``); ``t_end`` (s):
    end time (default the scenario's); ``out``: write the events to this CSV file (JSON
    when it ends in .json); ``plot``: write a figure to this file (needs matplotlib).

    Before the run, ``out`` and ``plot`` are checked to be writable (``ValueError`` if
    their directory is missing, they name a directory, or permission is lacking); a write
    that fails after the run raises ``rbimpact.errors.OutputError`` (an ``OSError``) whose
    ``summary`` is the run's summary.
    """
    from . import scenarios
    from ._validate import writable_path
    for what, path in (("out", out), ("plot", plot)):
        if path:
            writable_path(what, path)
    settings = list(settings or ())
    if any(str(x).split("=", 1)[0].strip() == "help" for x in settings):
        s = scenarios.spec(name)
        return "\n".join([f"{name}: {s.summary}", "parameters:"]
                         + [f"  {p.describe()}" for p in s.params.values()])
    params = scenarios.parse_settings(name, settings)
    if law is not None:
        params["law"] = law
    sc = scenarios.get(name, **params)
    if t_end is not None:
        from ._validate import real
        try:
            t = real("t_end", t_end, "s")
        except ValueError as exc:
            raise ValueError(f"t_end must be a positive number of seconds: {exc}") from None
        if not t > 0.0:
            raise ValueError(f"t_end must be a positive number of seconds, got {t_end!r}")
    t_end = sc.t_end if t_end is None else float(t_end)
    if hasattr(sc, "report"):      # a many-body scenario (granular_gas) runs and reports itself
        return sc.report(t_end=t_end, out=out, plot=plot)

    from .errors import NoSolutionError, SimulationError
    try:
        result, warm, cold = _timed_run(sc, t_end)
    except (SimulationError, NoSolutionError) as exc:
        partial = getattr(exc, "result", None)
        text = str(exc)
        if partial is not None:
            from .errors import OutputError
            try:
                part = _summary(name, sc, partial, t_end, None, None, out, plot, failed=True)
            except OutputError as oe:
                part = oe.summary + "\n" + str(oe)
            text += "\n--- the run up to the error ---\n" + part
        new = type(exc)(text, exc.mode_code) if isinstance(exc, NoSolutionError) \
            else type(exc)(text)
        new.result = partial
        raise new from exc
    return _summary(name, sc, result, t_end, warm, cold, out, plot)


def _summary(name, sc, result, t_end, warm, cold, out, plot, failed=False):
    from . import scenarios
    events = result.events
    kinds = [str(k) for k in events["kind"]]
    n_impacts = kinds.count("impact")
    others = {}
    for k in kinds:
        if k != "impact":
            others[k] = others.get(k, 0) + 1
    t_stop = result.t_end
    e0, e1 = (float(x) for x in np.asarray(result.energy(np.array([0.0, t_stop]))).ravel())

    impacts = events[np.array([k == "impact" for k in kinds], dtype=bool)]
    gains = impacts["dE"][_energy_gain(impacts, abs(e0) + abs(e1))]
    may = sc.law.may_create_energy
    if gains.size:
        created = (f"energy created: {gains.sum():.6g} J in {gains.size} impact(s), largest "
                   f"{gains.max():.3g} J ({sc.law.name} "
                   f"{'may create energy' if may else 'should never create energy: a BUG'})")
    else:
        created = ("energy created: none"
                   + (f" ({sc.law.name} may create energy, but did not here)" if may
                      else f" ({sc.law.name} never creates energy)"))

    law_text = ", ".join(f"{k}={v!r}" if isinstance(v, str) else f"{k}={v:g}"
                         for k, v in sc.law.params_dict.items() if k != "tol")
    changed = {k: v for k, v in sc.params.items()
               if k != "law" and v != scenarios.spec(name).params[k].default}
    other = ", ".join(f"{k} {v}" for k, v in sorted(others.items()))
    lines = [
        f"scenario: {name}: {scenarios.spec(name).summary}",
        f"law: {sc.law.name} ({law_text})"
        + (f"; pair laws: {len(sc.pair_laws)}" if sc.pair_laws else ""),
    ]
    if changed:
        lines.append("settings: " + ", ".join(f"{k}={v}" for k, v in changed.items()))
    lines += [
        f"status: {'stopped by the error above' if failed else result.status}, ran to "
        f"t = {t_stop:.6g} s of {t_end:.6g} s (policy {result.policy})",
        f"events: {n_impacts} impact{'' if n_impacts == 1 else 's'}"
        + (f", other events: {other}" if other else ", no other events"),
        f"energy: start {e0:.6g} J, end {e1:.6g} J (change {e1 - e0:+.6g} J)",
        created,
    ]
    if warm is not None:
        lines.append(
            f"run time: {_fmt_time(warm)} warm (first call {_fmt_time(cold)}, about "
            f"{_fmt_time(max(cold - warm, 0.0))} of it compiling or loading compiled code)"
            if cold is not None else
            f"run time: {_fmt_time(warm)} (single run, includes any compilation)")
    lines += _reference_lines(sc, events, result)
    unwritten = []     # (what, path, OSError): reported after the summary is complete
    if out:
        try:
            (result.to_json if str(out).endswith(".json") else result.to_csv)(out)
            lines.append(f"events written to {out}")
        except OSError as exc:
            unwritten.append(("out", out, exc))
    if plot:
        try:
            result.plot(plot)
            lines.append(f"plot written to {plot}")
        except OSError as exc:
            unwritten.append(("plot", plot, exc))
    text = "\n".join(lines)
    if unwritten:
        from .errors import OutputError
        raise OutputError("; ".join(f"could not write {what} {str(path)!r}: "
                                    f"{exc.strerror or exc}" for what, path, exc in unwritten),
                          summary=text, paths=[p for _, p, _ in unwritten])
    return text


def _energy_gain(impacts, e_scale):
    """Impacts whose dE exceeds round-off: dE > ENERGY_GAIN_RTOL * sum |P| (|v_i| + |v_f|)/2
    (the scale of the dot product defining dE, J) and dE > ENERGY_GAIN_EFLOOR * e_scale
    (J; the scene's energy: contact velocities that cancel to ~0 carry the round-off of the
    body velocities, not their own); boolean array."""
    if len(impacts) == 0:
        return np.zeros(0, dtype=bool)
    scale = 0.5 * np.sum(np.abs(impacts["P"]) * (np.abs(impacts["v_i"])
                                                 + np.abs(impacts["v_f"])), axis=-1)
    return (impacts["dE"] > ENERGY_GAIN_RTOL * scale) & (
        impacts["dE"] > ENERGY_GAIN_EFLOOR * e_scale)
