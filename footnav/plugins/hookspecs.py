"""The whole plugin contract of footnav: four hooks, each handed a ``register`` callback.

A plugin package declares ``[project.entry-points.footnav] myplugin = "myplugin.module"`` and
implements any of these hooks in that module with ``@footnav.hookimpl``.
"""

from __future__ import annotations

from collections.abc import Callable

import pluggy

PROJECT = "footnav"
ENTRY_POINT_GROUP = "footnav"

hookspec = pluggy.HookspecMarker(PROJECT)
hookimpl = pluggy.HookimplMarker(PROJECT)

#: ``register(cls, name=None)``: ``cls`` a component class; ``name`` overrides ``cls.name``. ``cls``
#: may be ``"package.module:Class"`` with ``name`` given: imported when first used.
Register = Callable[..., None]


@hookspec
def footnav_register_detectors(register: Register) -> None:
    """Register stance detector classes (subclasses of ``footnav.StanceDetector``).

    Example::

        @footnav.hookimpl
        def footnav_register_detectors(register):
            register(MyDetector)
    """


@hookspec
def footnav_register_estimators(register: Register) -> None:
    """Register per-foot estimator classes (subclasses of ``footnav.FootEstimator``).

    Example::

        @footnav.hookimpl
        def footnav_register_estimators(register):
            register(MyEstimator, name="my-ekf")
    """


@hookspec
def footnav_register_fusions(register: Register) -> None:
    """Register dual-foot fusion classes (subclasses of ``footnav.Fusion``).

    Example::

        @footnav.hookimpl
        def footnav_register_fusions(register):
            register(MyFusion)
    """


@hookspec
def footnav_register_heading_aids(register: Register) -> None:
    """Register heading aid classes (subclasses of ``footnav.HeadingAid``).

    Example::

        @footnav.hookimpl
        def footnav_register_heading_aids(register):
            register(MyHeadingAid)
    """
