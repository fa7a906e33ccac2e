"""What 2D and 3D results share: sample-time checks, writing the event log as CSV or JSON,
and loading pyplot.

A result class deriving from ``ResultBase`` defines ``FIELDS_CSV`` (the flat column names),
``_EVENT_VECTORS`` (the vector fields of its events record, in column order) and
``_json_bodies()`` (its body properties for the JSON header)."""
import csv
import json
import math

import numpy as np


class ResultBase:
    """Base of ``Result`` and ``Result3D``: ``_times`` (sample-time check), ``to_csv(path)`` and ``to_json(path)`` over
    ``self.events``."""

    FIELDS_CSV = ()
    _EVENT_VECTORS = ()

    def _rows(self):
        for ev in self.events:
            vectors = [float(x) for name in self._EVENT_VECTORS for x in ev[name]]
            yield (float(ev["t"]), str(ev["kind"]), int(ev["a"]), int(ev["b"]), *vectors,
                   int(ev["mode"]), float(ev["dE"]), int(ev["cluster"]))

    def _json_bodies(self):
        raise NotImplementedError

    #: slack (relative to max(1 s, |t_end|)) on the simulated interval for sample times
    TIME_SLACK = 1e-12

    def _times(self, times):
        """``times`` (s) as a finite 1-D float array inside [t_start, t_end]."""
        t = np.atleast_1d(np.asarray(times, dtype=float))
        if t.ndim != 1:
            raise ValueError("times must be a scalar or a 1-D array of times (s)")
        if not np.all(np.isfinite(t)):
            raise ValueError("times must be finite")
        slack = self.TIME_SLACK * max(1.0, abs(self.t_end))
        if t.size and (t.min() < self.t_start - slack or t.max() > self.t_end + slack):
            raise ValueError(f"times must lie in the simulated interval [{self.t_start:g}, "
                             f"{self.t_end:g}] s, got [{t.min():g}, {t.max():g}]")
        return t

    def to_csv(self, path):
        """Write the events to ``path`` as CSV (one header line; contact-space columns
        normal first; ``b < 0`` is plane ``-1 - b``; floats round-trip exactly)."""
        with open(path, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(self.FIELDS_CSV)
            for row in self._rows():
                w.writerow([repr(x) if isinstance(x, float) else x for x in row])

    def to_json(self, path):
        """Write the run's metadata and events to ``path`` as JSON."""
        doc = {
            "status": self.status, "policy": self.policy, "law": self.law,
            "t_start": self.t_start, "t_end": self.t_end, "t_requested": self.t_requested,
            "n_bodies": self.n_bodies, **self._json_bodies(),
            "gravity": self.gravity.tolist(),
            "tolerances": {k: (v if not isinstance(v, float) or math.isfinite(v) else str(v))
                           for k, v in self.tolerances.items()},
            "fields": list(self.FIELDS_CSV),
            "events": [dict(zip(self.FIELDS_CSV, row)) for row in self._rows()],
        }
        with open(path, "w") as f:
            json.dump(doc, f, indent=1)


def pyplot(what):
    """matplotlib.pyplot on the Agg backend, or an ImportError naming the ``plot`` extra."""
    try:
        import matplotlib
        matplotlib.use("Agg", force=False)
        import matplotlib.pyplot as plt
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError(f"{what} needs matplotlib: pip install 'rbimpact[plot]'") from exc
    return plt
