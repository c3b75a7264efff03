"""The pipeline factory: compose a detector, a per-foot estimator and a fusion by name.

Nothing here knows any particular component: names are resolved through the plugin registry, so a
new component needs no edit to this file.
"""

from __future__ import annotations

import copy
import sys
import time
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path as FilePath
from typing import TYPE_CHECKING, Any, Literal, cast

import numpy as np

from footnav.core.component import Component, FootEstimator, Fusion, HeadingAid, StanceDetector, require_stepable
from footnav.core.errors import (
    CompositionError,
    DataNotFoundError,
    DataQualityWarning,
    FootnavError,
    InvalidInputError,
    InvalidParameterError,
    PluginError,
)
from footnav.core.parameters import check_param_names
from footnav.core.types import FootTrajectory, FusionResult, ImuData, Recording, StanceResult
from footnav.core.types._derived import sharing
from footnav.core.warning_log import merge_warnings, recording, warn
from footnav.nav.floors import LEVEL_RISE_MAX_M, hold_result_floors
from footnav.nav.stance_check import check_stances
from footnav.nav.vertical_check import check_vertical
from footnav.pipeline.result import PipelineResult
from footnav.pipeline.sync import ClockSync, recording_exchanges

if TYPE_CHECKING:
    from footnav.pipeline.online import OnlineStream
    from footnav.plugins.registry import Registry

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on 3.10 only
    import tomli as tomllib

__all__ = [
    "Pipeline",
    "make_detector",
    "make_estimator",
    "make_fusion",
    "make_heading_aid",
    "make_pipeline",
    "load_pipeline",
    "list_components",
]

_BASES = {"detector": StanceDetector, "estimator": FootEstimator, "fusion": Fusion, "heading_aid": HeadingAid}


def _registry() -> Registry:
    from footnav.plugins.manager import get_registry

    return get_registry()


def list_components() -> dict[str, list[str]]:
    """Registered component names by kind: ``{"detector": [...], "estimator": [...], "fusion": [...],
    "heading_aid": [...]}``."""
    reg = _registry()
    return {kind: reg.names(kind) for kind in _BASES}


def make_detector(name: str, **params: Any) -> StanceDetector:
    """A stance detector by registry name, e.g. ``make_detector("threshold", window_s=0.2)``."""
    return cast(StanceDetector, _registry().create("detector", name, **params))


def make_estimator(name: str, **params: Any) -> FootEstimator:
    """A per-foot estimator by registry name, e.g. ``make_estimator("ekf", zupt_std_mps=0.02)``."""
    return cast(FootEstimator, _registry().create("estimator", name, **params))


def make_fusion(name: str, **params: Any) -> Fusion:
    """A dual-foot fusion by registry name, e.g. ``make_fusion("independent")``."""
    return cast(Fusion, _registry().create("fusion", name, **params))


def make_heading_aid(name: str, **params: Any) -> HeadingAid:
    """A heading aid by registry name, e.g. ``make_heading_aid("dominant-directions")``."""
    return cast(HeadingAid, _registry().create("heading_aid", name, **params))


def _resolve(kind: str, spec: Any, params: Mapping[str, Any] | None) -> Component:
    """Component from a name, an instance or a TOML-style table ``{"name": ..., **params}``."""
    base = _BASES[kind]
    if isinstance(spec, base):
        if params:
            raise InvalidParameterError(
                f"{kind} was given as an instance ({spec!r}); pass its parameters to its constructor, "
                f"not as {kind}_params"
            )
        return spec
    if isinstance(spec, Component):
        raise CompositionError(f"{spec!r} is a {spec.kind}; it cannot be used as the {kind}")
    if isinstance(spec, Mapping):
        table = dict(spec)
        if "name" not in table:
            raise InvalidParameterError(f"{kind} table {table!r} has no 'name' key")
        name = table.pop("name")
        table.update(params or {})
        return _registry().create(kind, name, **table)
    if isinstance(spec, str):
        return _registry().create(kind, spec, **dict(params or {}))
    raise InvalidParameterError(f"{kind} must be a registered name, a {base.__name__} or a table; got {spec!r}")


class Pipeline:
    """A composed [sync ->] detector -> estimator -> fusion [-> heading aid] chain. Build it with
    :func:`make_pipeline`.

    ``run`` checks that the components fit the data (two feet, magnetometer) before any work.
    ``sync`` (:class:`footnav.pipeline.sync.ClockSync`, optional) first puts both feet on one clock.
    ``heading_aid`` (optional; None or ``"none"``: no aid) corrects the fused trajectories' heading.
    """

    def __init__(
        self,
        detector: StanceDetector,
        estimator: FootEstimator,
        fusion: Fusion,
        sync: ClockSync | None = None,
        heading_aid: HeadingAid | None = None,
    ) -> None:
        self.detector = detector
        self.estimator = estimator
        self.fusion = fusion
        self.sync = sync
        self.heading_aid = heading_aid

    @property
    def _aid(self) -> HeadingAid | None:
        """The heading aid that does something (None for none)."""
        aid = self.heading_aid
        return None if aid is None or aid.name == "none" else aid

    def __repr__(self) -> str:
        shown = "" if self.sync is None else f", sync={self.sync!r}"
        shown += "" if self.heading_aid is None else f", heading_aid={self.heading_aid!r}"
        return f"Pipeline(detector={self.detector!r}, estimator={self.estimator!r}, fusion={self.fusion!r}{shown})"

    @property
    def components(self) -> tuple[Component, ...]:
        """detector, estimator, fusion, and the heading aid when one was given."""
        return (self.detector, self.estimator, self.fusion) + (() if self.heading_aid is None else (self.heading_aid,))

    def config(self) -> dict[str, dict[str, Any]]:
        """``{"detector": {"name": ..., **params}, ...}``: the tables of the pipeline's TOML file
        (and ``"sync"``: the clock sync's parameters, when the pipeline has one)."""
        # None (a value fitted or taken from the data, an unset leading_foot) has no TOML
        # spelling: a missing key means it, so a None is left out where it is the default
        tables = {c.kind: {"name": c.name, **_without_default_none(c)} for c in self.components}
        if self.sync is not None:
            tables["sync"] = {k: v for k, v in self.sync.get_params().items() if v is not None}
        return tables

    def to_toml(self) -> str:
        """The pipeline as TOML text that :func:`load_pipeline` reads back."""
        lines = []
        for kind, table in self.config().items():
            lines.append(f"[{kind}]")
            lines.extend(f"{key} = {_toml_value(value)}" for key, value in table.items())
            lines.append("")
        return "\n".join(lines)

    def check(self, *, n_feet: int, magnetometer: bool) -> None:
        """Raise CompositionError when a component needs what the data do not have."""
        for c in self.components:
            if c.needs_two_feet and n_feet < 2:
                raise CompositionError(
                    f"{c.kind} {c.name!r} needs both feet, but only one foot's data were given (pass right=...)"
                )
            if c.needs_magnetometer and not magnetometer:
                raise CompositionError(f"{c.kind} {c.name!r} needs a magnetometer, but the data have none")
        if getattr(self.fusion, "needs_stepable_estimator", False):
            require_stepable(self.fusion, self.estimator)
        if self.sync is not None:
            self.sync.validate_params()
            if self.sync.needs_two_feet and n_feet < 2:
                raise CompositionError(
                    f"clock sync {self.sync.method!r} aligns the feet with each other; it needs both feet's data"
                )

    @staticmethod
    def _origin(comp: Component) -> str:
        try:
            return _registry().get(comp.kind, comp.name).origin
        except FootnavError:
            return type(comp).__module__

    @contextmanager
    def _blame(self, *components: Component) -> Iterator[None]:
        """Turn an unexpected exception of a third-party component into a PluginError naming it.

        ``SystemExit`` too: a plugin that calls ``sys.exit`` must not end the user's program (the
        CLI exited 0 with no results). Ctrl-C (KeyboardInterrupt) passes.
        """
        try:
            yield
        except FootnavError:
            raise
        except (Exception, SystemExit) as exc:
            for comp in components:
                origin = self._origin(comp)
                if origin != "footnav":
                    raise PluginError(
                        f"{comp.kind} {comp.name!r} from {origin} failed: {type(exc).__name__}: {exc} "
                        f"(a bug in that package; the other components are unaffected)"
                    ) from exc
            raise

    def _faulty(self, comp: Component, what: str) -> Exception:
        """The error for a component whose output breaks its contract: a PluginError naming a
        third-party package, a RuntimeError (a bug to report) for footnav's own."""
        origin = self._origin(comp)
        if origin != "footnav":
            return PluginError(f"{comp.kind} {comp.name!r} from {origin} {what} (a bug in that package)")
        return RuntimeError(f"footnav's {comp.kind} {comp.name!r} {what}; please report this bug")

    def _check_stance_output(self, stance: Any, imu: ImuData | None, foot: str) -> None:
        if imu is None:
            return
        if not isinstance(stance, StanceResult):
            raise self._faulty(
                self.detector, f"returned {type(stance).__name__} for the {foot} foot, not a StanceResult"
            )
        if len(stance.mask) != imu.n_samples:
            raise self._faulty(
                self.detector,
                f"returned a stance mask of {len(stance.mask)} samples for the {foot} foot's {imu.n_samples}",
            )

    def _check_fused_output(self, fused: Any, left: ImuData, right: ImuData | None) -> None:
        culprit = self.fusion if self._origin(self.fusion) != "footnav" else self.estimator
        if not isinstance(fused, FusionResult):
            raise self._faulty(self.fusion, f"returned {type(fused).__name__}, not a FusionResult")
        for foot, traj, imu in (("left", fused.left, left), ("right", fused.right, right)):
            if imu is None:
                continue
            if traj is None or len(traj.t) != imu.n_samples:
                n = "no trajectory" if traj is None else f"a trajectory of {len(traj.t)} samples"
                raise self._faulty(culprit, f"returned {n} for the {foot} foot's {imu.n_samples} samples")
            # one flat reduction first: the per-row one is needed only to name the bad rows
            if np.isfinite(traj.position).all():
                continue
            bad = ~np.isfinite(traj.position).all(axis=1)
            if bad.any():
                raise self._faulty(
                    culprit,
                    f"returned non-finite positions for the {foot} foot (first at sample {int(np.argmax(bad))}, "
                    f"{int(bad.sum())} in all)",
                )

    def _check_stances(
        self, left: ImuData, stance_left: StanceResult, right: ImuData | None, stance_right: StanceResult | None
    ) -> dict[str, Any]:
        """Each foot's stances against its gait cycles (:mod:`footnav.nav.stance_check`); warns
        (DataQualityWarning) when they disagree."""
        out: dict[str, Any] = {}
        for foot, imu, stance in (("left", left, stance_left), ("right", right, stance_right)):
            if imu is None or stance is None:
                continue
            check = check_stances(imu, stance)
            out[foot] = check.as_meta()
            if check.suspicious:
                warn(check.message(foot, self.detector.name), DataQualityWarning, stacklevel=3)
        return out

    def _hold_floors(self, fused: FusionResult) -> FusionResult:
        """The estimator's vertical model on the final trajectories: with ``vertical="floors"``
        (the ekf's default) level strides are held level (:func:`footnav.nav.floors.hold_floors`),
        after the fusion so that every fusion, and the online stream, gets the same."""
        if getattr(self.estimator, "vertical", "free") != "floors":
            return fused
        bound = getattr(self.estimator, "level_rise_max_m", LEVEL_RISE_MAX_M)
        return hold_result_floors(fused, level_rise_max_m=bound)

    def _check_vertical(self, left: FootTrajectory, right: FootTrajectory | None) -> dict[str, Any]:
        """Each foot's height trend over its level strides (:mod:`footnav.nav.vertical_check`);
        warns (DataQualityWarning) when it is a steady drift."""
        out: dict[str, Any] = {}
        for foot, traj in (("left", left), ("right", right)):
            if traj is None:
                continue
            check = check_vertical(traj)
            out[foot] = check.as_meta()
            if check.suspicious:
                warn(check.message(foot, self.estimator.name), DataQualityWarning, stacklevel=3)
        return out

    def run(self, left: ImuData | Recording, right: ImuData | None = None) -> PipelineResult:
        """Detect stance, estimate each foot and fuse.

        Parameters
        ----------
        left
            The left foot (or the only foot), or a whole :class:`Recording`; a pandas DataFrame
            with columns ``t, acc_x..gyr_z`` in SI units is read with :meth:`ImuData.from_dataframe`.
        right
            The right foot (ImuData or DataFrame), or None for a one-foot recording.
        """
        exchanges = {}
        if isinstance(left, Recording):
            if right is not None:
                raise InvalidInputError("give either a Recording or left/right ImuData, not both", field="right")
            exchanges = recording_exchanges(left)
            right, left = left.right, left.left  # right first: mypy narrows left as it assigns
        left = ImuData.from_dataframe(left) if hasattr(left, "columns") and hasattr(left, "iloc") else left
        right = ImuData.from_dataframe(right) if hasattr(right, "columns") and hasattr(right, "iloc") else right
        for name, imu in (("left", left), ("right", right)):
            if imu is not None and not isinstance(imu, ImuData):
                raise InvalidInputError(f"expected ImuData, got {type(imu).__name__}", field=name)
        if left is None:
            raise InvalidInputError("no data for the left (or only) foot", field="left")
        self.check(n_feet=1 if right is None else 2, magnetometer=left.has_mag and (right is None or right.has_mag))
        t0 = time.perf_counter()
        # the inputs' provenance as given, before any component could touch it
        inputs = {
            "left": copy.deepcopy(dict(left.meta)),
            "right": None if right is None else copy.deepcopy(dict(right.meta)),
        }
        # this run's warnings, not another thread's (core/warning_log.py); what the checks, the
        # detector and the stance self-check derive from the same arrays is computed once
        with recording() as caught, sharing():
            for imu in (left, right):  # inside: what the checks find is recorded with the run
                if imu is not None:
                    imu.check_units()
            synced = None
            if self.sync is not None:
                synced = self.sync.align(left, right, exchanges=exchanges)
                left, right = synced.left, synced.right
            with self._blame(self.detector):
                stance_left, stance_right = self.detector.detect_pair(left, right)
            self._check_stance_output(stance_left, left, "left")
            self._check_stance_output(stance_right, right, "right")
            stance_checks = self._check_stances(left, stance_left, right, stance_right)
            # the fusion drives the estimator: a failure inside names whichever is not footnav's
            with self._blame(self.fusion, self.estimator):
                fused = self.fusion.fuse(self.estimator, left, stance_left, right, stance_right)
            self._check_fused_output(fused, left, right)
            if self._aid is not None:
                with self._blame(self._aid):
                    fused = self._aid.correct(fused, left, right)
                self._check_fused_output(fused, left, right)
            fused = self._hold_floors(fused)
            vertical_checks = self._check_vertical(fused.left, fused.right)
        from footnav._version import __version__

        meta = {
            "pipeline": self.config(),
            "footnav_version": __version__,
            # what reading the files said (footnav.load records it with the data), then the run's
            "warnings": merge_warnings(
                *(x.meta.get("read_warnings", ()) for x in (left, right) if x is not None), caught
            ),
            "stance_check": stance_checks,
            "vertical_check": vertical_checks,
            # what the fusion computed (update counts, fitted values, suspended turns, the span)
            "fusion": copy.deepcopy(dict(fused.meta)),
            **({} if synced is None else {"sync": synced.record()}),
            "runtime_s": time.perf_counter() - t0,
            "input": inputs,
        }
        return PipelineResult(
            left=fused.left,
            right=fused.right,
            path=fused.path,
            stance_left=stance_left,
            stance_right=stance_right,
            meta=meta,
        )

    def online(self, feet: int = 2, **options: Any) -> OnlineStream:
        """The pipeline on a live stream: push chunks of samples as they arrive, get what became
        final (:class:`footnav.pipeline.online.OnlineStream`; options ``max_wait_s``,
        ``clock_offset_s``, ``clocks``, ``keep``). Refused (CompositionError) for components that need the
        whole walk.

        Examples
        --------
        >>> pipe = make_pipeline("threshold", "ekf", estimator_params={"smoother": "step"})
        >>> stream = pipe.online(feet=2)
        >>> update = stream.push(left=chunk_left, right=chunk_right)  # doctest: +SKIP
        >>> result = stream.close()  # doctest: +SKIP
        """
        from footnav.pipeline.online import OnlineStream

        if self.sync is not None:
            raise CompositionError(
                f"clock sync {self.sync.method!r} needs the whole recording; online, give each foot's clock as "
                "clocks={'right': ClockMap} (e.g. fit_clock on the exchanges logged before the walk) or clock_offset_s="
            )
        return OnlineStream(self, feet=feet, **options)


def _without_default_none(component: Component) -> dict[str, Any]:
    defaults = {info.name: info.default for info in component.parameter_info()}
    return {k: v for k, v in component.get_params().items() if not (v is None and defaults.get(k) is None)}


def _toml_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    raise InvalidParameterError(f"parameter value {value!r} cannot be written to TOML")


def make_pipeline(
    detector: str | StanceDetector | Mapping[str, Any] = "adaptive",
    estimator: str | FootEstimator | Mapping[str, Any] = "ekf",
    fusion: str | Fusion | Mapping[str, Any] = "independent",
    *,
    detector_params: Mapping[str, Any] | None = None,
    estimator_params: Mapping[str, Any] | None = None,
    fusion_params: Mapping[str, Any] | None = None,
    sync: str | ClockSync | Mapping[str, Any] | None = None,
    heading_aid: str | HeadingAid | Mapping[str, Any] | None = None,
    heading_aid_params: Mapping[str, Any] | None = None,
) -> Pipeline:
    """Compose a pipeline from registered names, component instances or TOML-style tables.

    ``sync`` adds the clock-synchronisation stage before stance detection: ``"data"`` or
    ``"exchanges"`` (the method of :class:`footnav.pipeline.sync.ClockSync`), a ClockSync, or a
    table of its parameters (``{"method": "data", "drift": True}``); None (default) takes the
    feet to be on one clock already. ``heading_aid`` adds a heading aid after the fusion
    (``"dominant-directions"``, docs/heading.md); None (default) or ``"none"``: no aid.

    Examples
    --------
    >>> pipe = make_pipeline("threshold", "ekf", "independent", estimator_params={"zupt_std_mps": 0.02})
    >>> result = pipe.run(left=left_imu, right=right_imu)  # doctest: +SKIP
    >>> synced = make_pipeline(sync="data")  # the right foot's clock found from the data
    """
    aid = None  # no aid unless one (or its parameters) is given
    if heading_aid is not None or heading_aid_params:
        aid = _resolve("heading_aid", heading_aid or "none", heading_aid_params)
    return Pipeline(
        detector=cast(StanceDetector, _resolve("detector", detector, detector_params)),
        estimator=cast(FootEstimator, _resolve("estimator", estimator, estimator_params)),
        fusion=cast(Fusion, _resolve("fusion", fusion, fusion_params)),
        sync=_resolve_sync(sync),
        heading_aid=cast("HeadingAid | None", aid),
    )


def _resolve_sync(spec: str | ClockSync | Mapping[str, Any] | None) -> ClockSync | None:
    if spec is None or isinstance(spec, ClockSync):
        return spec
    if isinstance(spec, str):
        sync = ClockSync(cast("Literal['data', 'exchanges']", spec))  # validate_params below checks it
    elif isinstance(spec, Mapping):
        table = dict(spec)
        table.pop("name", None)  # written by Pipeline.config for symmetry with the other tables
        check_param_names(ClockSync, table)
        sync = ClockSync(**table)
    else:
        raise InvalidParameterError(f"sync must be 'data', 'exchanges', a ClockSync or a table; got {spec!r}")
    sync.validate_params()
    return sync


def load_pipeline(path: str | FilePath) -> Pipeline:
    """Read a pipeline TOML file: tables ``[detector]``, ``[estimator]``, ``[fusion]`` and
    optionally ``[heading_aid]``, each with a ``name`` and the component's parameters (missing
    tables take the defaults), and optionally ``[sync]``."""
    path = FilePath(path)
    if not path.is_file():
        raise DataNotFoundError(f"pipeline file {str(path)!r} does not exist")
    try:
        config = tomllib.loads(path.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as exc:
        raise InvalidInputError(f"not valid TOML: {exc}", path=str(path)) from None
    except RecursionError:  # tomllib parses nested arrays and tables recursively
        raise InvalidInputError(
            "not a pipeline file: arrays or tables nested too deeply to read", path=str(path)
        ) from None
    unknown = set(config) - set(_BASES) - {"sync"}
    if unknown:
        raise InvalidParameterError(
            f"{path}: unknown table(s) {sorted(unknown)}; a pipeline file has [detector], [estimator], [fusion] "
            "and optionally [heading_aid] and [sync]"
        )
    defaults = {"detector": "adaptive", "estimator": "ekf", "fusion": "independent", "heading_aid": None}
    try:
        return make_pipeline(**{kind: config.get(kind, defaults[kind]) for kind in _BASES}, sync=config.get("sync"))
    except InvalidParameterError as exc:
        raise InvalidParameterError(f"{path}: {exc}") from None
