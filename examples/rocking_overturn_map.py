"""Rocking-block overturn map over slenderness and initial tilt rate, against Housner's
threshold (a worked example of ``rbimpact.sweep``).

    python examples/rocking_overturn_map.py --out docs/rocking_overturn_map.png

The ``rocking_block`` scenario drops a block of width ``WIDTH`` and height ``h`` (the
slenderness is h / WIDTH), tilted by ``ANGLE`` with its lowest corner ``DROP`` above a
rough floor, spinning counter-clockwise at ``omega`` (the initial tilt rate, which turns it
further over that corner). Corner impacts are plastic (e = 0, Routh's law, mu = 1: the
corner sticks), so the block pivots on its corner and either falls back (and rocks down
to rest) or tips over. A run has overturned when its final angle is past the tipping angle
alpha = atan(WIDTH / h).

Housner's classical threshold for these assumptions: the plastic, sticking impact at the
corner keeps the angular momentum about it, so the block leaves the impact rotating at
omega I_G / I_O = omega / 4 about the corner (I_G = m R^2 / 3, I_O = 4 m R^2 / 3, R the
half-diagonal); it tips over when that kinetic energy exceeds the climb of the centre of
mass to above the corner, m g R (1 - cos(alpha - ANGLE)):

    omega > omega_H = 4 sqrt(3 g (1 - cos(alpha - ANGLE)) / (2 R)).

Needs the sweep extra and matplotlib.
"""
import argparse
import time

import numpy as np

import rbimpact

WIDTH = 0.05          # m
ANGLE = 0.05          # rad, initial tilt
DROP = 1e-6           # m, lowest corner above the floor at the start
G = 9.81
FIXED = {"e": [0.0], "mu": [1.0], "width": [WIDTH], "angle": [ANGLE], "drop": [DROP]}


def housner(slenderness, angle=ANGLE, width=WIDTH, g=G):
    """omega_H (rad/s): the initial spin above which the block tips over its corner."""
    s = np.asarray(slenderness, float)
    alpha = np.arctan(1.0 / s)
    R = 0.5 * width * np.hypot(1.0, s)
    return 4.0 * np.sqrt(1.5 * g * (1.0 - np.cos(alpha - angle)) / R)


def classify(df):
    """Column "outcome": "overturned", "upright" or "error"."""
    alpha = np.arctan(df["width"] / df["height"])
    over = np.abs(df["angle_final"]) > alpha
    out = np.where(over, "overturned", "upright")
    return df.assign(slenderness=df["height"] / df["width"],
                     outcome=np.where(df["status"] == "error", "error", out))


def plot(df, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 5.0))
    style = {"overturned": dict(marker="s", color="tab:red", ms=5),
             "upright": dict(marker="s", color="tab:blue", ms=5, alpha=0.5),
             "error": dict(marker="x", color="0.2", ms=6)}
    for kind, kw in style.items():
        part = df[df["outcome"] == kind]
        ax.plot(part["slenderness"], part["omega"], ls="none",
                label=f"{kind} ({len(part)})", **kw)
    s = np.geomspace(df["slenderness"].min(), df["slenderness"].max(), 200)
    ax.plot(s, housner(s), color="k", lw=1.5,
            label="Housner threshold (plastic sticking corner)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("slenderness h / b")
    ax.set_ylabel("initial tilt rate omega (rad/s)")
    ticks = [1, 1.5, 2, 3, 4, 6, 8]
    ax.set_xticks(ticks)
    ax.set_xticklabels([f"{t:g}" for t in ticks])
    ax.minorticks_off()
    ax.set_title(f"rocking_block: b = {WIDTH * 100:g} cm, tilt {ANGLE} rad, e = 0, mu = 1 "
                 f"(Routh); {len(df)} runs of 1 s", fontsize=9)
    ax.set_yticks([1, 2, 5, 10, 20, 50])
    ax.set_yticklabels(["1", "2", "5", "10", "20", "50"])
    fig.legend(fontsize=8, loc="lower center", ncol=2, frameon=False)
    fig.tight_layout(rect=(0, 0.1, 1, 1))
    fig.savefig(path, dpi=80)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", required=True, help="the figure (.png)")
    ap.add_argument("--slenderness", type=int, default=16, help="grid points in h / b")
    ap.add_argument("--rates", type=int, default=20, help="grid points in omega")
    ap.add_argument("--workers", type=int, default=2, help="Dask LocalCluster workers")
    ap.add_argument("--table", default=None, help="keep the table here (.parquet; resumed)")
    args = ap.parse_args(argv)
    slender = np.round(np.geomspace(1.0, 8.0, args.slenderness), 4)
    grid = {"height": [float(WIDTH * s) for s in slender],
            "omega": [float(x) for x in np.round(np.geomspace(1.0, 80.0, args.rates), 4)],
            **FIXED}
    t0 = time.perf_counter()
    df = rbimpact.sweep("rocking_block", law="routh", grid=grid, workers=args.workers,
                        out=args.table)
    seconds = time.perf_counter() - t0
    df = classify(df)
    plot(df, args.out)
    ok = df[df["outcome"] != "error"]
    predicted = ok["omega"] > housner(ok["slenderness"])
    agree = (predicted == (ok["outcome"] == "overturned"))
    print(f"{len(df)} runs in {seconds:.1f} s ({df.attrs['ran']} computed now); figure: "
          f"{args.out}")
    print(f"outcomes: {df['outcome'].value_counts().to_dict()}; Housner's threshold agrees "
          f"on {int(agree.sum())} of {len(ok)} runs")
    for _, r in ok[~agree].iterrows():
        print(f"  differs: h/b = {r.slenderness:.3f}, omega = {r.omega:.3f} rad/s "
              f"(omega_H = {housner(r.slenderness):.3f}): {r.outcome}, final angle "
              f"{r.angle_final:.3f} rad")
    for _, r in df[df["outcome"] == "error"].iterrows():
        print(f"  error: h/b = {r.slenderness:.3f}, omega = {r.omega:.3f}: {r.error[:120]}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
