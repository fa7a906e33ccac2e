"""The ``rbimpact`` command line. Each subcommand imports only what it needs."""
import argparse
import os
import sys

import numpy as np

from .errors import NoSolutionError, SimulationError

# DESIGN §5 case 1b: rod at 45 degrees, v = (-1, 1), e = 1, mu = 0.3
CASE_1B = {"v": [-1.0, 1.0], "W": [2.5, -1.5, -1.5, 2.5], "e": 1.0, "mu": 0.3}


def _contact(args):
    v = np.array(args.v if args.v is not None else CASE_1B["v"], dtype=float)
    d = v.shape[0]
    if d not in (2, 3):
        raise ValueError(f"--v takes 2 (2D) or 3 (3D) numbers, normal first; got {d}")
    w = args.W if args.W is not None else CASE_1B["W"]
    if len(w) != d * d:
        raise ValueError(f"--W takes {d * d} numbers (row-major {d}x{d}) for a {d}D contact; "
                         f"got {len(w)}")
    return v, np.array(w, dtype=float).reshape(d, d)


def _cmd_laws(args):
    from .laws import LAWS, Law
    from .errors import NoSolutionError
    v, W = _contact(args)
    e = CASE_1B["e"] if args.e is None else args.e
    mu = CASE_1B["mu"] if args.mu is None else args.mu
    print(f"v = {v.tolist()}  W = {W.tolist()}  e = {e:g}  mu = {mu:g}  e_t = {args.e_t:g}")
    rows = []
    for name, spec in LAWS.items():
        kinds = ("energetic", "poisson", "newton") if name == "routh" else (None,)
        for kind in kinds:
            params = {"e": e, "mu": mu}
            if "e_t" in spec.params:
                params["e_t"] = args.e_t
            if kind is not None:
                params["restitution"] = kind
                params["tol"] = args.tol
            label = name if kind is None else f"routh/{kind}"
            try:
                imp = Law(name, **params).resolve(v, W)
            except NoSolutionError:
                rows.append((label, "-", "-", "no solution", "-", "-"))
                continue
            mode = imp.mode if len(imp.phases) < 2 else "->".join(imp.phases)
            rows.append((label, _vec(imp.P), _vec(imp.v_f), mode, f"{imp.dE:+.6f}",
                         "YES" if imp.energy_gain else "no"))
    _table(("law", "P", "v_f", "mode", "dE [J]", "energy created"), rows)
    return 0


def _vec(x):
    return "(" + ", ".join(f"{c:+.6f}" for c in x) + ")"


def _table(header, rows):
    widths = [max(len(str(r[i])) for r in (header, *rows)) for i in range(len(header))]
    line = "  ".join("{:<%d}" % w for w in widths)
    print(line.format(*header))
    print("  ".join("-" * w for w in widths))
    for r in rows:
        print(line.format(*map(str, r)))


def _cmd_bench(args):
    from . import bench
    try:
        return bench.main(args.what, repeat=args.repeat, json_path=args.json)
    except OSError as exc:              # the figures are printed already
        if args.json and getattr(exc, "filename", None) == args.json:
            args._unwritten.append(f"could not write --json {args.json!r}: "
                                   f"{exc.strerror or exc}")
            return 0
        raise


def _cmd_impulse_space(args):
    from .impulse_region import impulse_space_report
    v, W = _contact(args)
    mu = CASE_1B["mu"] if args.mu is None else args.mu
    if not args.plot:
        print(impulse_space_report(v, W, mu, n=args.n))
        return 0
    from .impulse_region import impulse_space
    space = impulse_space(v, W, mu, n=args.n)
    print(space.summary(), flush=True)
    print()
    _write(args, "--plot", args.plot, space.plot, "plot written to {}")
    return 0


def _cmd_crosscheck(args):
    from . import crosscheck
    text, rows = crosscheck.crosscheck_report(args.name, dts=args.dt, repeat=args.repeat,
                                              law=args.law, settings=args.set)
    print(text, flush=True)
    # the files are written here, after the table is printed, so that a failed write
    # (checked beforehand, but a disk can fill up) does not lose the run
    _write(args, "--out", args.out, lambda p: crosscheck._write_csv(p, rows),
           "table written to {}")
    pm = [r for r in rows if r["engine"] == "pymunk"]
    _write(args, "--plot", args.plot, lambda p: crosscheck._plot(
        p, rows, crosscheck._order([r["dt_s"] for r in pm], [r["error_m"] for r in pm]),
        args.name, rows[-1]["law"], not rows[-1]["reference"]), "plot written to {}")
    return 0


def _write(args, what, path, write, done):
    """Write one output file after the command's output; an OSError is remembered on
    ``args`` and reported by ``main`` as one line (exit status 2)."""
    if not path:
        return
    try:
        write(path)
    except OSError as exc:
        args._unwritten.append(f"could not write {what} {str(path)!r}: {exc.strerror or exc}")
        return
    print(done.format(path))


def _cmd_stability(args):
    if args.replay is not None or args.scenes is not None:
        from .campaign import main as campaign_main
        return campaign_main(args)
    from .stability import stability_report, write_csv
    text, rows, ok = stability_report(quick=args.quick)
    print(text, flush=True)
    _write(args, "--out", args.out, lambda p: write_csv(rows, p), "table written to {}")
    return 0 if ok else 1


def _positive_int(text):
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a positive integer, got {text!r}") from None
    if n < 1:
        raise argparse.ArgumentTypeError(f"must be a positive integer (>= 1), got {text!r}")
    return n


#: the options of each command that name a file to write (checked before the command runs)
OUTPUTS = {"run": ("out", "plot"), "crosscheck": ("out", "plot"), "bench": ("json",),
           "impulse-space": ("plot",), "stability": ("out",), "sweep": ("out",)}


def _cmd_list(args):
    from .run import list_text
    print(list_text())
    return 0


def _cmd_run(args):
    from .errors import OutputError
    from .run import run_scenario
    try:
        text = run_scenario(args.name, law=args.law, settings=args.set, t_end=args.t_end,
                            out=args.out, plot=args.plot)
    except OutputError as exc:          # the run finished; a file could not be written
        print(exc.summary)
        args._unwritten.append(str(exc).replace("could not write out ", "could not write "
                                                "--out ").replace("could not write plot ",
                                                                  "could not write --plot "))
        return 0
    print(text)
    return 0


def _cmd_sweep(args):
    from .sweep import sweep_command
    print(sweep_command(args.name, law=args.law, grid=args.grid, seeds=args.seeds,
                        workers=args.workers, scheduler=args.scheduler, out=args.out))
    return 0


def _parser():
    p = argparse.ArgumentParser(prog="rbimpact", description="Algebraic collision laws "
                                "with friction and an exact event-driven rigid-body stepper.")
    sub = p.add_subparsers(dest="command", required=True)

    def contact(q):
        q.add_argument("--v", type=float, nargs="+", metavar="X",
                       help="relative contact velocity, normal first (m/s); default: case 1b")
        q.add_argument("--W", type=float, nargs="+", metavar="X",
                       help="Delassus matrix, row-major (1/kg); default: case 1b")

    q = sub.add_parser("laws", help="apply every law to one contact")
    contact(q)
    q.add_argument("--e", type=float, help="normal restitution (default 1)")
    q.add_argument("--mu", type=float, help="friction coefficient (default 0.3)")
    q.add_argument("--e-t", dest="e_t", type=float, default=0.0,
                   help="tangential restitution for Brach and Chatterjee-Ruina (default 0)")
    q.add_argument("--tol", type=float, default=1e-10, help="Routh 3D tolerance (default 1e-10)")
    q.set_defaults(func=_cmd_laws)

    q = sub.add_parser("bench", help="benchmarks: figures and ratios measured in one run")
    q.add_argument("what", nargs="?", default="laws",
                   choices=("laws", "routh3d", "rotation3d", "stepper", "crosscheck",
                            "compile", "pay", "sweep", "manybody", "memory", "all"))
    q.add_argument("--repeat", type=_positive_int, default=7,
                   help="repeats per figure (median), >= 1")
    q.add_argument("--json", help="also write the figures to this JSON file")
    q.set_defaults(func=_cmd_bench)

    q = sub.add_parser("impulse-space", help="what each law can reach in impulse space")
    contact(q)
    q.add_argument("--mu", type=float, help="friction coefficient (default 0.3)")
    q.add_argument("--n", type=_positive_int, default=200, help="samples per curve")
    q.add_argument("--plot", help="write the figure to this PNG file")
    q.set_defaults(func=_cmd_impulse_space)

    q = sub.add_parser("list", help="list the scenarios")
    q.set_defaults(func=_cmd_list)

    q = sub.add_parser("run", help="run a scenario with the event-driven stepper")
    q.add_argument("name")
    q.add_argument("--law", help="collision law (default: the scenario's)")
    q.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="scenario parameter (repeatable)")
    q.add_argument("--t-end", dest="t_end", type=float, help="end time (s)")
    q.add_argument("--out", help="write the events to CSV (or JSON if it ends in .json)")
    q.add_argument("--plot", help="write a plot to this PNG file (needs the plot extra)")
    q.set_defaults(func=_cmd_run)
    q = sub.add_parser("crosscheck",
                       help="cross-check a scenario against pymunk: error against run time")
    q.add_argument("name")
    q.add_argument("--dt", type=float, nargs="+", default=[1e-2, 1e-3, 1e-4, 1e-5],
                   help="pymunk time steps (s)")
    q.add_argument("--repeat", type=_positive_int, default=3,
                   help="repeats per timing (median), >= 1")
    q.add_argument("--out", help="write the table to this CSV file")
    q.add_argument("--plot", help="write the work-precision plot to this PNG file")
    q.add_argument("--law", help="collision law (default kane_levinson, pymunk's own)")
    q.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="scenario parameter (repeatable)")
    q.set_defaults(func=_cmd_crosscheck)

    q = sub.add_parser("stability", help="stiff and extreme cases for every law and the "
                       "stepper (exits 1 if any breaks)")
    q.add_argument("--quick", action="store_true", help="a subset that runs in seconds")
    q.add_argument("--out", help="write the table to this CSV file")
    q.add_argument("--scenes", type=_positive_int, metavar="N",
                   help="run the randomized drop campaign instead: N scenes per dimension")
    q.add_argument("--dim", choices=("2", "3", "both"), default="both",
                   help="campaign: dimensions to draw (default both)")
    q.add_argument("--seed", type=int, default=0, help="campaign seed (default 0)")
    q.add_argument("--replay", metavar="DIM:SEED",
                   help="run one campaign scene (from a failure's reproducer) and explain it")
    q.add_argument("--bodies", type=int, choices=(1, 2, 3), default=1,
                   help="campaign: 1 body dropped (default), 2 bodies thrown at each other "
                   "in flight (2D or 3D, issue 16), or 3 bodies dropped into a stack on a "
                   "floor (2D)")
    q.add_argument("--planar", action="store_true",
                   help="campaign: the 3D drop scenes made planar (rotation about y, motion "
                   "in the xz plane: exact zeros where random scenes have round-off)")
    q.set_defaults(func=_cmd_stability)

    q = sub.add_parser("sweep", help="run a scenario over a grid of parameters, laws and "
                       "seeds, on Dask (needs the sweep extra)")
    q.add_argument("name")
    q.add_argument("--law", action="append", metavar="LAW[,LAW...]",
                   help="collision law(s) (repeatable; default: the scenario's)")
    q.add_argument("--grid", action="append", default=[], metavar="KEY=V1,V2,...",
                   help="a scenario parameter and its values (repeatable)")
    q.add_argument("--seeds", type=_positive_int, default=1,
                   help="seeds 0..N-1 of each grid point (default 1)")
    q.add_argument("--workers", type=_positive_int, default=1,
                   help="processes of a Dask LocalCluster (default 1: in this process)")
    q.add_argument("--scheduler", metavar="ADDRESS",
                   help="use the running Dask cluster at this address instead")
    q.add_argument("--out", metavar="FILE.parquet",
                   help="write the table here as runs finish; runs already in it are skipped")
    q.set_defaults(func=_cmd_sweep)
    return p


def _one_line(exc):
    return " ".join(str(exc).split()) or type(exc).__name__


def main(argv=None):
    """Run the command line; returns the exit status: 0 done, 1 the run stopped with a
    ``NoSolutionError``/``SimulationError`` (or a stability cell failed), 2 bad arguments
    or an output file that cannot be written (one line on stderr, after the command's
    output), 130 interrupted (Ctrl-C)."""
    args = _parser().parse_args(argv)
    args._unwritten = []
    where = f"rbimpact {args.command}"
    try:
        from ._validate import writable_path
        for opt in OUTPUTS.get(args.command, ()):   # before a run that may take long
            path = getattr(args, opt, None)
            if path:
                writable_path(f"--{opt}", path)
        status = args.func(args)
    except KeyboardInterrupt:
        print(f"{where}: interrupted (Ctrl-C)", file=sys.stderr)
        return 130
    except BrokenPipeError:         # output piped into `head`: stop quietly, as cat does
        try:
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        except (OSError, ValueError, AttributeError):
            pass
        return 141
    except ImportError as exc:
        print(f"{where}: error: {_one_line(exc)} (pip install -e '.[test]' or "
              f"'.[plot]' for the optional pieces)", file=sys.stderr)
        return 2
    except (ValueError, TypeError) as exc:
        print(f"{where}: error: {_one_line(exc)}", file=sys.stderr)
        return 2
    except (NoSolutionError, SimulationError) as exc:
        print(f"{where}: {type(exc).__name__}: {exc}", file=sys.stderr)
        return 1
    except OSError as exc:
        print(f"{where}: error: {_one_line(exc)}", file=sys.stderr)
        return 2
    if args._unwritten:
        sys.stdout.flush()
        print(f"{where}: error: " + "; ".join(args._unwritten), file=sys.stderr)
        return 2
    return status


if __name__ == "__main__":
    sys.exit(main())
