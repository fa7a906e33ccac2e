"""Die-toss face frequencies per collision law and friction coefficient, with Wilson 95 %
confidence intervals (a worked example of ``rbimpact.sweep``).

    python examples/die_toss_frequencies.py --out docs/die_toss_frequencies.png

A fair cube thrown with a uniformly random orientation must come up on each face with
probability 1/6 whatever the collision law: the plot checks that every law and friction
coefficient gives frequencies consistent with 1/6 (and a chi-square p-value per law), and
counts the tosses that did not end at rest on a face (errors). Every toss of the sweep is
a row of the table (``--table`` keeps it, as Parquet, and a second call reuses it).
Needs the sweep extra and matplotlib.
"""
import argparse
import time

import numpy as np

import rbimpact

LAWS = ("kane_levinson", "brach", "smith", "routh", "chatterjee_ruina")
LABELS = {"kane_levinson": "Kane & Levinson", "brach": "Brach", "smith": "Smith",
          "routh": "Routh", "chatterjee_ruina": "Chatterjee & Ruina"}
MUS = (0.1, 0.3, 0.6)
Z95 = 1.959963984540054


def wilson(k, n, z=Z95):
    """Wilson score interval (lower, upper) of a binomial proportion k/n."""
    k, n = np.asarray(k, float), np.asarray(n, float)
    p = k / n
    den = 1.0 + z * z / n
    centre = (p + z * z / (2 * n)) / den
    half = z / den * np.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return centre - half, centre + half


def counts(df):
    """(law, mu) -> (faces 1..6 counts, tosses, unresolved)."""
    out = {}
    for (law, mu), part in df.groupby(["law", "mu"], sort=False):
        faces = part["face"].dropna().astype(int)
        c = np.array([(faces == f).sum() for f in range(1, 7)])
        out[law, mu] = (c, len(part), len(part) - int(c.sum()))
    return out


def plot(df, path, seeds):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from scipy.stats import chisquare
    table = counts(df)
    fig, axes = plt.subplots(1, len(MUS), figsize=(12, 4.2), sharey=True)
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    faces = np.arange(1, 7)
    for ax, mu in zip(axes, MUS):
        ax.axhline(1 / 6, color="0.4", lw=1, ls="--", zorder=0)
        ax.text(0.02, 0.09, "chi-square p:", transform=ax.transAxes, fontsize=7)
        ax.text(0.02, 0.03, "errors:", transform=ax.transAxes, fontsize=7)
        for i, law in enumerate(LAWS):
            c, n, bad = table[law, mu]
            m = int(c.sum())
            lo, hi = wilson(c, m)
            p = c / m
            x = faces + (i - 2) * 0.13
            ax.errorbar(x, p, yerr=[p - lo, hi - p], fmt="o", ms=3.5, capsize=2, lw=1,
                        color=colors[i], label=LABELS[law] if mu == MUS[0] else None)
            ax.text(0.3 + 0.14 * i, 0.09, f"{chisquare(c).pvalue:.2f}", color=colors[i],
                    transform=ax.transAxes, fontsize=7)
            ax.text(0.3 + 0.14 * i, 0.03, f"{bad}", color=colors[i],
                    transform=ax.transAxes, fontsize=7)
        ax.set_title(f"mu = {mu}", fontsize=10)
        ax.set_xticks(faces)
        ax.set_xlabel("face up")
        ax.grid(axis="y", lw=0.3)
    axes[0].set_ylabel("frequency (Wilson 95 % CI)")
    axes[0].set_ylim(0.08, 0.235)
    fig.legend(loc="lower center", ncol=len(LAWS), fontsize=8, frameon=False)
    fig.suptitle(f"die_toss: {seeds} random tosses per law and mu ({len(df)} runs); "
                 f"dashed: 1/6; p: chi-square test of a fair die; errors: tosses not at "
                 f"rest on a face", fontsize=9)
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    fig.savefig(path, dpi=80)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", required=True, help="the figure (.png)")
    ap.add_argument("--seeds", type=int, default=1000, help="tosses per law and mu")
    ap.add_argument("--workers", type=int, default=2, help="Dask LocalCluster workers")
    ap.add_argument("--table", default=None, help="keep the table here (.parquet; resumed)")
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    df = rbimpact.sweep("die_toss", law=list(LAWS), grid={"mu": list(MUS)}, seeds=args.seeds,
                        workers=args.workers, out=args.table)
    seconds = time.perf_counter() - t0
    plot(df, args.out, args.seeds)
    table = counts(df)
    print(f"{len(df)} tosses in {seconds:.1f} s ({df.attrs['ran']} computed now); figure: "
          f"{args.out}")
    print(f"{'law':<18}{'mu':>5}  {'faces 1..6 (counts)':<34}{'unresolved':>10}")
    for (law, mu), (c, n, bad) in table.items():
        print(f"{law:<18}{mu:>5}  {' '.join(f'{x:4d}' for x in c):<34}{bad:>10}")
    errors = df[df["status"] == "error"]
    if len(errors):
        print(f"{len(errors)} runs ended in an error; the most frequent:")
        kinds = errors["error"].str.replace(r"[-+]?\d[\d.e+-]*", "#", regex=True)
        for text, k in kinds.str.slice(0, 110).value_counts().head(3).items():
            print(f"  {k} x {text}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
