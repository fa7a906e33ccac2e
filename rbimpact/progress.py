"""Progress bars for long commands: a tqdm bar on a terminal, silence otherwise.

    >>> from rbimpact.progress import progress
    >>> for case in progress(cases, desc="stability"):
    ...     run(case)

``progress`` shows a bar only when stderr is a terminal and tqdm is importable (it is in
the ``sweep`` extra); otherwise it returns the iterable unchanged, so logs, pipes and CI
stay clean. ``RBIMPACT_PROGRESS=0`` turns bars off, ``=1`` forces them (when tqdm is there).
"""
import os
import sys

__all__ = ["progress", "enabled"]


def enabled(stream=None):
    """True when a bar would be shown on ``stream`` (default stderr)."""
    flag = os.environ.get("RBIMPACT_PROGRESS", "").strip().lower()
    if flag in ("0", "false", "no", "off"):
        return False
    stream = sys.stderr if stream is None else stream
    if flag not in ("1", "true", "yes", "on"):
        try:
            if not stream.isatty():
                return False
        except (AttributeError, ValueError):      # no isatty, or a closed stream
            return False
    try:
        import tqdm  # noqa: F401
    except ImportError:
        return False
    return True


def progress(iterable, total=None, desc=None, unit="it", stream=None, **kwargs):
    """``iterable`` wrapped in a tqdm bar on ``stream`` (default stderr) when
    ``enabled(stream)``, else ``iterable`` itself. ``total``: its length when it has none
    (a generator, ``as_completed``); ``desc``: the label; other keywords go to tqdm."""
    if not enabled(stream):
        return iterable
    from tqdm import tqdm
    return tqdm(iterable, total=total, desc=desc, unit=unit,
                file=sys.stderr if stream is None else stream, dynamic_ncols=True,
                **kwargs)
