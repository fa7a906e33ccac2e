"""The scenario library: named multi-bounce scenes with their law and, where one exists,
an exact reference.

    >>> from rbimpact import scenarios
    >>> scenarios.names()
    ('billiards', 'bouncing_ball', ...)
    >>> sc = scenarios.get("bouncing_ball", e=0.8, h=1.0)
    >>> result = sc.simulate()            # Simulation(sc.scene, sc.law, ...).run(sc.t_end)

Every scenario is a builder function registered with ``@register(name, ...)``; its typed
keyword parameters (float, int, bool or str, all with defaults) are the scenario's
parameters. ``get`` checks names and types (``ValueError`` listing what is allowed) and
builds the scene only then: importing this package builds nothing, compiles nothing, and
imports neither pymunk nor matplotlib.

Every scenario has a ``law`` parameter (the law's name, one of the laws it declares) and
passes the collision parameters it has (``e``, ``mu``, ``e_t``, ``restitution``) to the
law that takes them, so swapping the law keeps them (``make_law``).
"""
import inspect
import math
import typing
from dataclasses import dataclass, field
from types import MappingProxyType

__all__ = ["Scenario", "ScenarioSpec", "Param", "FirstImpact", "names", "get", "spec",
           "register", "parse_settings", "make_law", "ALL_LAWS"]

#: every law of ``rbimpact.LAWS``, in the order the scenarios list them
ALL_LAWS = ("kane_levinson", "brach", "smith", "routh", "chatterjee_ruina")
#: law parameters a scenario may carry and hand to the law that takes them
LAW_PARAMS = ("e", "mu", "e_t", "restitution")
_TYPES = (float, int, bool, str)
#: help texts of the collision parameters, shared by the scenarios
LAW_HELP = {
    "e": "normal restitution (-); [0, 1], Brach [-1, 1]",
    "mu": "Coulomb friction coefficient (-), >= 0",
    "e_t": "tangential restitution (-) for Brach and Chatterjee-Ruina, [-1, 1]",
    "restitution": "Routh's termination: energetic (Stronge), poisson or newton",
}
#: allowed values of the str collision parameters
LAW_CHOICES = {"restitution": ("energetic", "poisson", "newton")}
_TRUE = ("true", "1", "yes", "on")
_FALSE = ("false", "0", "no", "off")


@dataclass(frozen=True)
class Param:
    """One scenario parameter: its type (float, int, bool or str), default, help text
    (with its unit) and, for a str, the allowed values."""

    name: str
    type: type
    default: object
    help: str
    choices: tuple = None

    def describe(self):
        """``name (type, default ...)``: help, for listings and error messages."""
        extra = f"; one of {', '.join(self.choices)}" if self.choices else ""
        return (f"{self.name} ({self.type.__name__}, default {self.default!r}{extra}): "
                f"{self.help}")

    def coerce(self, value, scenario):
        """Check ``value`` against the type (ints are accepted for floats); return it."""
        t = self.type
        ok = (isinstance(value, t) and not (t is not bool and isinstance(value, bool)))
        if t is float and not ok:
            ok = (isinstance(value, (int, float)) or _is_numpy_real(value)) \
                and not isinstance(value, bool)
        if t is int and not ok:
            ok = _is_numpy_int(value)
        if t is bool and not ok:
            ok = type(value).__name__ == "bool_"
        if not ok:
            raise ValueError(f"scenario {scenario!r}: parameter {self.name!r} must be a "
                             f"{t.__name__}, got {value!r} ({type(value).__name__}); "
                             f"{self.describe()}")
        value = t(value)
        if t is float and not math.isfinite(value):
            raise ValueError(f"scenario {scenario!r}: parameter {self.name!r} must be "
                             f"finite, got {value!r}")
        if self.choices and value not in self.choices:
            raise ValueError(f"scenario {scenario!r}: parameter {self.name!r} must be one "
                             f"of {', '.join(self.choices)}; got {value!r}")
        return value

    def parse(self, text, scenario):
        """Parse a command-line string into this parameter's type (see ``coerce``)."""
        t = self.type
        s = text.strip()
        try:
            if t is bool:
                if s.lower() in _TRUE:
                    return True
                if s.lower() in _FALSE:
                    return False
                raise ValueError
            value = t(s) if t is not str else text
        except ValueError:
            what = ("true/false (also 1/0, yes/no, on/off)" if t is bool
                    else f"an {t.__name__}" if t is int else f"a {t.__name__}")
            raise ValueError(f"scenario {scenario!r}: parameter {self.name!r} must be "
                             f"{what}, got {text!r}; {self.describe()}") from None
        return self.coerce(value, scenario)


def _is_numpy_real(x):
    return type(x).__module__ == "numpy" and hasattr(x, "dtype") and x.dtype.kind in "fiu"


def _is_numpy_int(x):
    return type(x).__module__ == "numpy" and hasattr(x, "dtype") and x.dtype.kind in "iu"


@dataclass(frozen=True)
class ScenarioSpec:
    """A registered scenario: name, one-line summary, supported laws (the first is the
    default law), parameters (name -> ``Param``) and the builder function."""

    name: str
    summary: str
    laws: tuple
    params: typing.Mapping
    build: typing.Callable

    @property
    def default_law(self):
        return self.params["law"].default

    def check(self, params):
        """Validate keyword parameters; return the full dict (defaults filled in)."""
        unknown = [k for k in params if k not in self.params]
        if unknown:
            raise ValueError(f"scenario {self.name!r} has no parameter {unknown[0]!r}; "
                             f"its parameters are:\n  "
                             + "\n  ".join(p.describe() for p in self.params.values()))
        return {k: (p.coerce(params[k], self.name) if k in params else p.default)
                for k, p in self.params.items()}


@dataclass(frozen=True)
class Scenario:
    """A built scenario, ready to run.

    ``scene`` (``rbimpact.Scene2D``), ``law`` (``rbimpact.Law``), ``pair_laws`` (mapping
    for ``Simulation`` or None), ``t_end`` (s), ``laws`` (names of the laws it supports),
    ``params`` (the values used, law included), ``tolerances`` (keyword arguments for
    ``Simulation``), ``reference`` (None or an object with the exact answer),
    ``max_events`` (default event budget of ``simulate``), ``bodies`` (role -> body
    index), ``planes`` (role -> ``Plane`` returned by ``add_plane``; events name plane
    ``p`` as ``b = -1 - p.index``).
    """

    name: str
    description: str
    scene: object
    law: object
    pair_laws: object = None
    t_end: float = 1.0
    laws: tuple = ALL_LAWS
    params: typing.Mapping = field(default_factory=dict)
    tolerances: typing.Mapping = field(default_factory=dict)
    reference: object = None
    max_events: int = 1_000_000
    bodies: typing.Mapping = field(default_factory=dict)
    planes: typing.Mapping = field(default_factory=dict)

    def simulation(self, **tolerances):
        """A fresh ``rbimpact.Simulation`` of this scenario (tolerances override)."""
        from rbimpact import Simulation
        kw = {**self.tolerances, **tolerances}
        return Simulation(self.scene, self.law, pair_laws=self.pair_laws, **kw)

    def simulate(self, t_end=None, **run_kwargs):
        """Run to ``t_end`` (default ``self.t_end``, s) and return the ``Result``.

        Other keywords go to ``Simulation.run`` (``max_events`` defaults to
        ``self.max_events``)."""
        run_kwargs.setdefault("max_events", self.max_events)
        return self.simulation().run(self.t_end if t_end is None else t_end, **run_kwargs)


@dataclass(frozen=True)
class FirstImpact:
    """Exact time ``t1`` (s) of the first impact of a body released without rotation in
    free fall: its lowest point, ``gap`` (m) above the plane, falls under gravity ``g``
    (m/s^2) from vertical velocity ``vy`` (m/s)."""

    gap: float
    g: float
    vy: float = 0.0

    @property
    def t1(self):
        # gap + vy t - g t^2 / 2 = 0, the positive root, in a cancellation-free form
        s = math.sqrt(self.vy * self.vy + 2.0 * self.g * self.gap)
        return 2.0 * self.gap / (s - self.vy) if self.vy <= 0.0 else (self.vy + s) / self.g

    def __call__(self):
        return self.t1


_REGISTRY = {}


def register(name, *, laws, summary, help, choices=None):
    """Decorator registering a scenario builder under ``name``.

    The builder takes keyword parameters annotated float, int, bool or str, each with a
    default, one of them ``law: str`` (default: the default law), and returns a
    ``Scenario``. ``help`` maps every parameter but ``law`` to its help text (with its
    unit; ``LAW_HELP`` supplies e, mu, e_t and restitution); ``choices`` maps str
    parameters to their allowed values; ``laws`` names the laws the scenario supports.
    """
    laws = tuple(laws)
    bad = [x for x in laws if x not in ALL_LAWS]
    if bad or not laws:
        raise ValueError(f"scenario {name!r}: unknown laws {bad}; known: {ALL_LAWS}")
    choices = {**LAW_CHOICES, **(choices or {}), "law": laws}

    def deco(build):
        if name in _REGISTRY:
            raise ValueError(f"scenario {name!r} is already registered")
        hints = typing.get_type_hints(build)
        params = {}
        for p in inspect.signature(build).parameters.values():
            t = hints.get(p.name)
            if t not in _TYPES or p.default is inspect.Parameter.empty:
                raise TypeError(f"scenario {name!r}: parameter {p.name!r} needs a default and "
                                f"an annotation among float, int, bool, str")
            text = ("collision law" if p.name == "law"
                    else help.get(p.name, LAW_HELP.get(p.name)))
            if text is None:
                raise TypeError(f"scenario {name!r}: parameter {p.name!r} has no help text")
            ch = choices.get(p.name)
            params[p.name] = Param(p.name, t, p.default, text, tuple(ch) if ch else None)
        if "law" not in params or params["law"].default not in laws:
            raise TypeError(f"scenario {name!r}: needs a parameter law: str with a default "
                            f"among {laws}")
        _REGISTRY[name] = ScenarioSpec(name, summary, laws, MappingProxyType(params), build)
        return build

    return deco


def names():
    """Names of the registered scenarios, sorted (tuple of str)."""
    return tuple(sorted(_REGISTRY))


def spec(name):
    """The ``ScenarioSpec`` of ``name`` (``ValueError`` for an unknown name)."""
    try:
        return _REGISTRY[name]
    except (KeyError, TypeError):
        raise ValueError(f"unknown scenario {name!r}; known scenarios: "
                         f"{', '.join(names())}") from None


def get(name, **params):
    """Build scenario ``name`` with these parameters; returns a ``Scenario``.

    Unknown names, unknown parameters, ill-typed or out-of-range values raise
    ``ValueError`` saying what is allowed."""
    s = spec(name)
    if "law" in params and isinstance(params["law"], str) and params["law"] not in s.laws:
        raise ValueError(f"scenario {name!r} supports the laws {', '.join(s.laws)}; "
                         f"got law={params['law']!r}")
    values = s.check(params)
    try:
        return s.build(**values)
    except ValueError as exc:
        if str(exc).startswith("scenario"):
            raise
        raise ValueError(f"scenario {name!r}: {exc}") from exc


def parse_settings(name, settings):
    """Parse ``key=value`` strings (or a mapping of str to str) into typed parameters of
    scenario ``name`` (the ``--set`` options of ``rbimpact run``)."""
    s = spec(name)
    items = settings.items() if hasattr(settings, "items") else None
    if items is None:
        items = []
        for text in settings:
            key, sep, value = str(text).partition("=")
            if not sep or not key.strip():
                raise ValueError(f"setting {text!r} is not of the form key=value; parameters "
                                 f"of {name!r}: {', '.join(s.params)}")
            items.append((key.strip(), value))
    out = {}
    for key, value in items:
        if key not in s.params:
            s.check({key: None})  # raises the listing error
        out[key] = s.params[key].parse(value, name)
    return out


def make_law(name, **params):
    """``rbimpact.Law(name, ...)`` with those of ``params`` (e, mu, e_t, restitution)
    that law ``name`` takes; the others are dropped (e.g. ``e_t`` for Smith)."""
    from rbimpact.laws import LAWS, Law
    takes = LAWS[name].params
    return Law(name, **{k: v for k, v in params.items() if k in takes})


def law_params(values):
    """The collision parameters (e, mu, e_t, restitution) among a scenario's values."""
    return {k: values[k] for k in LAW_PARAMS if k in values}


def positive(scenario, **values):
    """Raise ``ValueError`` unless every value is > 0 (sizes, masses, speeds)."""
    for k, v in values.items():
        if not v > 0:
            raise ValueError(f"scenario {scenario!r}: {k} must be > 0, got {v!r}")


def nonnegative(scenario, **values):
    """Raise ``ValueError`` unless every value is >= 0."""
    for k, v in values.items():
        if not v >= 0:
            raise ValueError(f"scenario {scenario!r}: {k} must be >= 0, got {v!r}")


# Registration: importing the modules defines builders only (no scene is built).
from . import (billiards, bouncing_ball, bouncing_ellipse, falling_rod,  # noqa: E402,F401
               perforation, rocking_block, spinning_ball, superball)
from . import polygon_collide, rod_strikes_ball  # noqa: E402,F401  (2D body-body, issue 16)
from . import box_on_box  # noqa: E402,F401  (2D box-box and box-floor impacts, issue 16)
from . import box_stack  # noqa: E402,F401  (2D persistent body-body contact, issue 16)
from . import dominoes  # noqa: E402,F401  (2D persistent body-body contact, issue 16)
from . import painleve_rod  # noqa: E402,F401  (the Painleve paradox, issue 13)
from . import die_toss, spinning_ball_3d, superball_3d, tumbling_capsule  # noqa: E402,F401
from . import dice_collide  # noqa: E402,F401  (3D body-body impacts, issue 16)
from . import granular_gas  # noqa: E402,F401  (many-body: rbimpact.manybody)
from . import polygon_gas  # noqa: E402,F401  (2D many-body gas of polygons, issue 16)
