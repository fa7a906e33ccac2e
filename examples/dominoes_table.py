"""The dominoes table of the README: chains of 3, 5 and 8 dominoes at mu 0.3, 0.5 and 0.8
(Kane & Levinson, e = 0), each run's status, toppled count, events, last strike, last
front speed, the first strike's error against the closed form, and the warm run time
(median of 3). Run: ``python examples/dominoes_table.py``."""
import time

import numpy as np

from rbimpact import scenarios


def main():
    print("| count | mu | status | toppled | events | last strike (s) | last front speed (m/s) "
          "| first strike error | warm run (ms) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for count in (3, 5, 8):
        for mu in (0.3, 0.5, 0.8):
            sc = scenarios.get("dominoes", count=count, mu=mu)
            try:
                r = sc.simulation().run(sc.t_end)
            except Exception as exc:        # a named refusal: its first line
                print(f"| {count} | {mu} | {str(exc).splitlines()[0][:120]} |")
                continue
            ts = []
            for _ in range(3):
                t0 = time.perf_counter()
                sc.simulation().run(sc.t_end)
                ts.append(time.perf_counter() - t0)
            ref = sc.reference
            hits = ref.hits(r.events)
            v = ref.speeds(r.events)
            err = abs(hits[0] - ref.t1) / ref.t1
            print(f"| {count} | {mu} | {r.status} | {int(ref.toppled(r).sum())}/{count} | "
                  f"{len(r.events)} | {hits[-1]:.4f} | {v[-1]:.3f} | {err:.1e} | "
                  f"{np.median(ts) * 1e3:.0f} |")


if __name__ == "__main__":
    main()
