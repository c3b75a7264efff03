"""A component's parameters: the unit its name carries, its description, and the checks of its value.

Parameters carry their unit in their name (``window_s``, ``sigma_acc_mps2``, ``..._sqrthz``:
:func:`unit_of`) and are described in the class's numpydoc ``Parameters`` section
(:func:`docstring_parameters`), from which :meth:`footnav.core.component.Component.parameter_info`
builds the table that ``footnav plugins`` and the docs show. A component's ``validate_params``
checks each value with :func:`require` and :func:`require_in_range` against the bounds below
(docs/reliability.md lists them).
"""

from __future__ import annotations

import inspect
import math
import os
import re
from collections.abc import Mapping
from dataclasses import dataclass
from numbers import Integral, Real
from typing import TYPE_CHECKING, Any

from footnav.core.errors import InvalidParameterError

if TYPE_CHECKING:
    from footnav.core.component import Component

__all__ = [
    "ParameterInfo",
    "unit_of",
    "docstring_parameters",
    "check_param_names",
    "require",
    "is_number",
    "require_positive",
    "require_non_negative",
    "require_in_range",
    "worker_count",
    "MAX_DURATION_S",
    "MAX_RATE_RADPS",
    "MAX_ACC_MPS2",
    "MAX_LENGTH_M",
    "MAX_SPEED_MPS",
    "MAX_ANGLE_RAD",
    "MAX_SCALE_STD",
]

#: Unit suffix of a parameter name -> unit, longest suffix first.
_UNIT_SUFFIXES = (
    ("_radps2", "rad/s^2"),
    ("_mps3", "m/s^3"),
    ("_mps2", "m/s^2"),
    ("_radps", "rad/s"),
    ("_dps", "deg/s"),
    ("_mps", "m/s"),
    ("_deg", "deg"),
    ("_rad", "rad"),
    ("_hz", "Hz"),
    ("_mb", "MB"),
    ("_ms", "ms"),
    ("_s", "s"),
    ("_m", "m"),
    ("_g", "g"),
)
_SQRT_HZ = "_sqrthz"


def unit_of(name: str) -> str:
    """Unit named by a parameter's suffix (``sigma_acc_mps2_sqrthz`` -> ``m/s^2/sqrt(Hz)``), or ''."""
    per_root_hz = name.endswith(_SQRT_HZ)
    base = name[: -len(_SQRT_HZ)] if per_root_hz else name
    for suffix, unit in _UNIT_SUFFIXES:
        if base.endswith(suffix):
            return unit + ("/sqrt(Hz)" if per_root_hz else "")
    return ""


@dataclass(frozen=True)
class ParameterInfo:
    """One constructor parameter of a component: name, default, unit and description."""

    name: str
    default: Any
    unit: str
    description: str


def docstring_parameters(cls: type) -> dict[str, str]:
    """Descriptions of the numpydoc ``Parameters`` section of ``cls`` (first sentence each)."""
    doc = inspect.getdoc(cls) or ""
    match = re.search(r"^Parameters\n-+\n(.*?)(?:\n\n[A-Z][A-Za-z ]+\n-+\n|\Z)", doc, re.S | re.M)
    if not match:
        return {}
    out: dict[str, str] = {}
    current: list[str] = []
    names: list[str] = []
    for line in match.group(1).splitlines():
        if line and not line.startswith(" "):
            if names:
                for n in names:
                    out[n] = " ".join(current).strip()
            names = [n.strip() for n in line.split(":")[0].split(",")]
            current = []
        elif line.strip():
            current.append(line.strip())
    for n in names:
        out[n] = " ".join(current).strip()
    return out


def check_param_names(cls: type[Component], params: Mapping[str, Any]) -> None:
    """Raise InvalidParameterError for parameter names ``cls`` does not take, listing the valid ones."""
    valid = cls._param_names()
    unknown = [k for k in params if k not in valid]
    if unknown:
        import difflib

        hints = []
        for k in unknown:
            close = difflib.get_close_matches(k, valid, n=1)
            hints.append(f"{k!r}" + (f" (did you mean {close[0]!r}?)" if close else ""))
        raise InvalidParameterError(
            f"{cls.kind} {cls.name!r} has no parameter {', '.join(hints)}; "
            f"valid parameters: {', '.join(valid) or 'none'}"
        )


def require(condition: bool, component: Component, param: str, expected: str) -> None:
    """Raise InvalidParameterError unless ``condition``: names component, parameter, value, expectation."""
    if not condition:
        raise InvalidParameterError(
            f"{component.kind} {component.name!r}: parameter {param}={getattr(component, param)!r} is invalid; "
            f"expected {expected}"
        )


def is_number(value: Any) -> bool:
    """A finite real number (not a bool)."""
    return isinstance(value, Real) and not isinstance(value, bool) and math.isfinite(value)


def require_positive(component: Component, *names: str, high: float = math.inf) -> None:
    """InvalidParameterError naming the first of ``names`` that is not a number in (0, high]."""
    require_in_range(component, *names, low=0.0, high=high, low_open=True)


def require_non_negative(component: Component, *names: str, high: float = math.inf) -> None:
    """InvalidParameterError naming the first of ``names`` that is not a number in [0, high]."""
    require_in_range(component, *names, low=0.0, high=high)


# Upper bounds shared by the built-in components' parameters (listed in docs/reliability.md).
# Each lies far above any value that makes sense and far below where a value would exhaust
# memory or time (durations and rates multiply into sample counts) or overflow (standard
# deviations and noise densities are squared, 1e308 ** 2 is inf).
#: Windows, minimum durations, gait intervals in s: no gait event lasts a minute.
MAX_DURATION_S = 60.0
#: Angular rates (thresholds, noise, bias walks) in rad/s: 30x a 2000 deg/s full scale.
MAX_RATE_RADPS = 1000.0
#: Accelerations (thresholds, noise, bias walks) in m/s^2: about 100 g.
MAX_ACC_MPS2 = 1000.0
#: Lengths and their standard deviations in m (foot separation, step geometry).
MAX_LENGTH_M = 100.0
#: Velocity standard deviations in m/s.
MAX_SPEED_MPS = 100.0
#: Angle standard deviations in rad: above 2 pi an angle is not known at all.
MAX_ANGLE_RAD = 10.0
#: Scale-factor error standard deviations, a fraction: 1 is a sensor that reads anything.
MAX_SCALE_STD = 1.0


def _format_bound(value: float) -> str:
    return f"{value:g}" if math.isfinite(value) else ("inf" if value > 0 else "-inf")


def require_in_range(
    component: Component,
    *names: str,
    low: float,
    high: float,
    low_open: bool = False,
    high_open: bool = False,
    integer: bool = False,
) -> None:
    """InvalidParameterError naming the first of ``names`` outside ``low .. high``.

    The upper bounds of footnav's parameters are where a larger value would exhaust memory or
    time (windows and rates that multiply into sample counts) or overflow (a standard deviation
    is squared), set well above any value that makes sense; docs/reliability.md lists them.

    Parameters
    ----------
    component
        The component whose attributes are checked; the message names its kind and name.
    *names
        Parameter names sharing the range.
    low, high
        The bounds, included unless ``low_open`` / ``high_open``; ``high=math.inf`` for none.
    low_open, high_open
        Exclude the bound: ``low=0, low_open=True`` is "positive".
    integer
        Require an integer (``int`` or a numpy integer, not a bool) rather than a finite real.

    Raises
    ------
    InvalidParameterError
        Naming the component, the parameter, its value and the range with the parameter's unit,
        e.g. ``parameter window_s=1e+308 is invalid; expected a number in (0, 60] s``.
    """
    left = "(" if low_open else "["
    right = ")" if high_open or not math.isfinite(high) else "]"
    for name in names:
        value = getattr(component, name)
        kind_ok = (isinstance(value, Integral) and not isinstance(value, bool)) if integer else is_number(value)
        ok = kind_ok and (value > low if low_open else value >= low) and (value < high if high_open else value <= high)
        if not ok:  # the message only when needed: online mode checks parameters on every push
            unit = unit_of(name)
            expected = (
                f"{'an integer' if integer else 'a number'} in {left}{_format_bound(low)}, {_format_bound(high)}{right}"
                + (f" {unit}" if unit else "")
            )
            require(ok, component, name, expected)


def worker_count(jobs: Any, owner: str, name: str = "n_jobs") -> int:
    """The number of worker processes ``jobs`` asks for: a positive int, or -1 for every core.

    Raises
    ------
    InvalidParameterError
        For anything else (0, below -1, a bool, not an int), naming ``owner`` and ``name``.
    """
    if not isinstance(jobs, Integral) or isinstance(jobs, bool) or jobs == 0 or jobs < -1:
        raise InvalidParameterError(f"{owner}: {name}={jobs!r} is invalid; expected a positive int or -1 (all cores)")
    return (os.cpu_count() or 1) if jobs == -1 else int(jobs)
