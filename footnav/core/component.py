"""Base classes of footnav's components: detectors, estimators, fusions, heading aids.

A component follows scikit-learn's contract: the constructor takes keyword-only parameters, stores
them unchanged under the same names and does nothing else; ``get_params`` / ``set_params`` /
``clone`` make any configuration reproducible and printable; validation happens when the action
method starts (``validate_params``). Parameters carry their unit in their name (``window_s``,
``sigma_acc_mps2``) and are described in the class's numpydoc ``Parameters`` section, from which
:meth:`Component.parameter_info` builds the table that ``footnav plugins`` and the docs show.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any, ClassVar, Protocol, runtime_checkable

from footnav.core.errors import CompositionError
from footnav.core.parameters import ParameterInfo, check_param_names, docstring_parameters, unit_of

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

    from footnav.core.types import FootTrajectory, FusionResult, ImuData, StanceResult

__all__ = [
    "Component",
    "StanceDetector",
    "FootEstimator",
    "Fusion",
    "FusionSession",
    "HeadingAid",
    "JointFilter",
    "StepableEstimator",
    "KINDS",
]


class Component:
    """Base of every footnav component.

    Subclasses set ``name`` (the registry name), ``kind`` (set by the three bases below) and
    declare what they need with ``needs_two_feet`` and ``needs_magnetometer``.
    """

    kind: ClassVar[str] = ""
    name: ClassVar[str] = ""
    needs_two_feet: ClassVar[bool] = False
    needs_magnetometer: ClassVar[bool] = False
    _param_names_cache: ClassVar[tuple[Any, tuple[str, ...]]]  # set per class by _param_names

    # -- parameters ---------------------------------------------------------------------------
    @classmethod
    def _param_names(cls) -> list[str]:
        # inspect.signature costs ~0.3 ms; online mode validates parameters on every push. Cached
        # per class (in its own __dict__: a subclass has its own constructor) and per __init__, so
        # a class whose constructor is replaced afterwards is read again.
        cached = cls.__dict__.get("_param_names_cache")
        if cached is None or cached[0] is not cls.__init__:
            sig = inspect.signature(cls.__init__)
            names = tuple(
                p.name
                for p in sig.parameters.values()
                if p.name != "self" and p.kind in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD)
            )
            cached = (cls.__init__, names)
            cls._param_names_cache = cached
        return list(cached[1])

    @classmethod
    def parameter_info(cls) -> list[ParameterInfo]:
        """Every constructor parameter with its default, unit (from the name) and description."""
        sig = inspect.signature(cls.__init__)
        docs = docstring_parameters(cls)
        return [
            ParameterInfo(name=n, default=sig.parameters[n].default, unit=unit_of(n), description=docs.get(n, ""))
            for n in cls._param_names()
        ]

    def get_params(self, deep: bool = True) -> dict[str, Any]:
        """The constructor parameters as a dict (re-creates the component with ``type(self)(**p)``).

        ``deep`` is scikit-learn's signature (``sklearn.base.clone`` passes ``deep=False``);
        footnav components hold no nested components, so both give the same dict.
        """
        return {n: getattr(self, n) for n in self._param_names()}

    def set_params(self, **params: Any) -> Component:
        """Set parameters by name; unknown names raise InvalidParameterError listing the valid ones."""
        check_param_names(type(self), params)
        for key, value in params.items():
            setattr(self, key, value)
        return self

    def clone(self, **overrides: Any) -> Component:
        """A new, unfitted component with the same parameters (and ``overrides``)."""
        params = self.get_params()
        check_param_names(type(self), overrides)
        params.update(overrides)
        return type(self)(**params)

    def validate_params(self) -> None:
        """Check parameter values; called by the action method. Subclasses extend it."""

    def __repr__(self) -> str:
        sig = inspect.signature(type(self).__init__)
        shown = []
        for name, value in self.get_params().items():
            default = sig.parameters[name].default
            try:
                same = bool(value == default)
            except Exception:  # array-valued parameters compare elementwise
                same = False
            if not same:
                shown.append(f"{name}={value!r}")
        return f"{type(self).__name__}({', '.join(shown)})"

    def describe(self) -> dict[str, Any]:
        """Kind, name and parameters: what provenance records and TOML re-creates."""
        return {"kind": self.kind, "name": self.name, "params": self.get_params()}


class StanceDetector(Component):
    """Finds the zero-velocity (stance) phases of a foot: ``detect(imu) -> StanceResult``.

    A detector that needs both feet (``needs_two_feet = True``) implements ``detect_pair``; the
    pipeline always calls ``detect_pair(left, right)``, whose default detects each foot alone.
    """

    kind: ClassVar[str] = "detector"

    @property
    def latency_s(self) -> float | None:
        """How long after a sample arrives its stance decision is final, s; None: unbounded
        (the detector needs the whole recording and cannot run online, :mod:`footnav.pipeline.online`).

        The default covers a windowed detector: the window ahead of the sample (half a centred
        window, ``window_s`` for ``combine="any"`` / ``"all"``), then ``min_stance_s`` to know a
        stance run is kept and ``min_swing_s`` to know a gap is not bridged. A detector without
        ``window_s`` declares None unless it overrides this.
        """
        window = getattr(self, "window_s", None)
        if window is None:
            return None
        ahead = window / 2 if getattr(self, "combine", "center") == "center" else window
        return float(ahead + getattr(self, "min_stance_s", 0.0) + getattr(self, "min_swing_s", 0.0))

    def detect(self, imu: ImuData) -> StanceResult:  # pragma: no cover - abstract
        """Stance of one foot.

        Parameters
        ----------
        imu
            The foot's :class:`~footnav.core.types.ImuData` (body frame, SI units).

        Returns
        -------
        StanceResult
            One flag per sample (True: the foot stands still), with the detector's ``meta``.
        """
        raise NotImplementedError

    def detect_pair(self, left: ImuData, right: ImuData | None) -> tuple[StanceResult, StanceResult | None]:
        """Stance of both feet; ``right`` may be None for one-foot detectors."""
        return self.detect(left), (None if right is None else self.detect(right))


class FootEstimator(Component):
    """Estimates one foot's trajectory: ``estimate(imu, stance) -> FootTrajectory``."""

    kind: ClassVar[str] = "estimator"

    def estimate(self, imu: ImuData, stance: StanceResult) -> FootTrajectory:  # pragma: no cover - abstract
        """One foot's trajectory.

        Parameters
        ----------
        imu
            The foot's :class:`~footnav.core.types.ImuData` (body frame, SI units).
        stance
            Its :class:`~footnav.core.types.StanceResult`.

        Returns
        -------
        FootTrajectory
            Position (m), velocity (m/s) and attitude [w, x, y, z] (body to nav) per sample, in
            the nav frame (z up, x the first step's direction).
        """
        raise NotImplementedError


@runtime_checkable
class JointFilter(Protocol):
    """The filter a coupled fusion advances, reads and updates: the feet in one error state.

    A :class:`StepableEstimator`'s ``start`` returns one. Feet are numbered in the order given to
    ``start`` (0 left, 1 right); positions in m and velocities in m/s in the nav frame (z up),
    quaternions [w, x, y, z] body to nav, times in s. Coupled fusions use these members and no
    others; :class:`footnav.estimators.ekf.InsFilter` is the reference implementation. (One
    optional extra: a filter with ``run_range_constrained(times, bound_m, std_m, symmetric,
    start)`` lets the ``range`` fusion check the feet's distance and project them inside it, as
    InsFilter does; without it the fusion does both in Python, to the same result within
    rounding.)
    """

    @property
    def covariance(self) -> NDArray[np.float64]:
        """The joint error-state covariance now, (N, N)."""
        ...

    def block(self, foot: int, name: str) -> slice:
        """The error-state columns of ``foot``'s block ``name`` (``"pos"``, ``"vel"``, ``"att"``)."""
        ...

    def time(self, foot: int) -> float:
        """Time of ``foot``'s last processed sample, s."""
        ...

    def index(self, foot: int) -> int:
        """Index of ``foot``'s last processed sample in its recording."""
        ...

    def position(self, foot: int) -> NDArray[np.float64]:
        """``foot``'s position now, (3,) m."""
        ...

    def velocity(self, foot: int) -> NDArray[np.float64]:
        """``foot``'s velocity now, (3,) m/s."""
        ...

    def quaternion(self, foot: int) -> NDArray[np.float64]:
        """``foot``'s attitude now, (4,)."""
        ...

    def outputs(self, foot: int) -> Sequence[NDArray[np.float64]]:
        """``foot``'s forward estimate per sample so far: attitude (K, 4), velocity (K, 3),
        position (K, 3), then anything else; a sample holds the estimate before any update at
        its instant."""
        ...

    def run_until(self, t_stop: float = ...) -> None:
        """Process every foot's samples up to time ``t_stop`` (s; all of them by default)."""
        ...

    def selection(self, indices: NDArray[np.int64]) -> NDArray[np.float64]:
        """H that measures the error states ``indices``, (len(indices), N)."""
        ...

    def update(
        self,
        h: NDArray[np.float64],
        innovation: NDArray[np.float64],
        r: float | NDArray[np.float64],
        *,
        gate: float | None = None,
    ) -> NDArray[np.float64] | None:
        """Kalman update with ``innovation = h(x^) - z = H dx + noise`` of variance ``r``; the
        correction applied, or None when ``gate`` rejected it."""
        ...

    def update_position(
        self, foot: int, z: NDArray[np.float64], std_m: float | NDArray[np.float64], axes: int = 3
    ) -> NDArray[np.float64] | None:
        """Position measurement ``z`` (m) of ``foot``'s first ``axes`` axes with std ``std_m``."""
        ...


@runtime_checkable
class StepableEstimator(Protocol):
    """An estimator coupled fusions can drive step by step (range, step-vector, particle, dtw).

    Besides the estimator's ``estimate`` and the component's ``clone`` it starts one joint filter
    over all the feet and finishes it with its own smoothing. Its constructor takes ``smoother``
    (``"none"`` among its values: the fusions' forward tracks) and ``heading`` (``"first-step"``
    among its values: ``estimate`` then turns the foot so that its first step points along +x
    and records the turn in ``meta["heading_rotation_rad"]``, which ``start`` takes as the
    initial yaw). Optionally ``closed_loop`` and ``closed_loop_std_m`` (Chistyakov et al. (2021),
    Alg. 1). footnav's ``ekf`` is the reference implementation; ``footnav.testing``'s
    ``StepableEstimatorContract`` runs every coupled fusion with a candidate.
    """

    smoother: str
    heading: str

    def start(
        self,
        imus: Sequence[ImuData],
        stances: Sequence[StanceResult],
        *,
        initial_yaw_rad: Sequence[float] | None = None,
        initial_position_m: Sequence[NDArray[np.float64]] | None = None,
    ) -> JointFilter:
        """A joint filter over ``imus``, each foot aligned at its first stance, its yaw (rad) and
        position (m) set as given, ready to run."""
        ...

    def finish(self, filt: JointFilter, stances: Sequence[StanceResult]) -> list[FootTrajectory]:
        """Run ``filt`` to the end, smooth as ``smoother`` says and return each foot's trajectory."""
        ...

    def estimate(self, imu: ImuData, stance: StanceResult) -> FootTrajectory:
        """One foot alone."""
        ...

    def clone(self, **overrides: Any) -> StepableEstimator:
        """The same estimator with ``overrides`` (e.g. ``smoother="none"``)."""
        ...


#: The members of :class:`StepableEstimator` a coupled fusion calls, and the constructor
#: parameters it sets (it clones the estimator into a forward filter with
#: ``clone(smoother="none", heading="first-step")``).
STEPABLE_METHODS = ("start", "finish", "estimate", "clone")
STEPABLE_PARAMS = ("smoother", "heading")
#: The members of :class:`JointFilter`.
JOINT_FILTER_MEMBERS = (
    "covariance",
    "block",
    "time",
    "index",
    "position",
    "velocity",
    "quaternion",
    "outputs",
    "run_until",
    "selection",
    "update",
    "update_position",
)


def stepable_gaps(estimator: Component) -> list[str]:
    """What ``estimator`` lacks of :class:`StepableEstimator`, the contract coupled fusions drive.

    Returns
    -------
    list of str
        The missing methods and parameters, e.g. ``["method finish", "parameter smoother"]``;
        empty when the estimator can be driven. (That the filter its ``start`` returns is a
        :class:`JointFilter` is checked when it runs: ``start`` needs the data.)
    """
    missing = [f"method {m}" for m in STEPABLE_METHODS if not callable(getattr(estimator, m, None))]
    params = estimator.get_params() if callable(getattr(estimator, "get_params", None)) else {}
    missing += [f"parameter {p}" for p in STEPABLE_PARAMS if p not in params]
    return missing


def require_stepable(fusion: Component, estimator: Component) -> None:
    """Raise CompositionError unless ``estimator`` meets the step-able filter contract
    (:func:`stepable_gaps`), naming what it lacks."""
    gaps = stepable_gaps(estimator)
    if gaps:
        raise CompositionError(
            f"fusion {fusion.name!r} drives the per-foot filters step by step and needs an estimator with a "
            f"step-able filter, such as 'ekf' (the contract: footnav.core.component.StepableEstimator); "
            f"{estimator.name!r} lacks {', '.join(gaps)}"
        )


class Fusion(Component):
    """Combines the feet into one pedestrian: ``fuse(estimator, left, stance_left, right, stance_right)``.

    A fusion drives the per-foot ``estimator`` (it may call ``estimator.estimate`` or step its
    filter) and returns a :class:`~footnav.core.types.FusionResult`.
    """

    kind: ClassVar[str] = "fusion"
    #: The fusion drives the estimator's step-able filter (``estimator.start``): checked by the
    #: pipeline before anything runs.
    needs_stepable_estimator: ClassVar[bool] = False

    def fuse(  # pragma: no cover
        self,
        estimator: FootEstimator,
        left: ImuData,
        stance_left: StanceResult,
        right: ImuData | None = None,
        stance_right: StanceResult | None = None,
    ) -> FusionResult:
        """Both feet's trajectories, and their path.

        Parameters
        ----------
        estimator
            The per-foot :class:`FootEstimator` the fusion drives.
        left, right
            Each foot's :class:`~footnav.core.types.ImuData`; ``right`` None for one foot.
        stance_left, stance_right
            Each foot's :class:`~footnav.core.types.StanceResult`.

        Returns
        -------
        FusionResult
            Each foot's :class:`~footnav.core.types.FootTrajectory` and the walk's path, nav frame.
        """
        raise NotImplementedError

    #: A coupled fusion whose work at a time needs no later sample offers :meth:`session`
    #: (online mode, :mod:`footnav.pipeline.online`); None: offline only.
    session: ClassVar[Callable[..., FusionSession] | None] = None
    #: Online, the session gives what ``fuse`` gives on the same samples; False when it learns
    #: as it goes what ``fuse`` takes from the whole walk (``close`` then reruns offline).
    online_exact: bool = True
    #: Online, the session is given each foot's own forward solution at its stance starts
    #: (``session.feet_alone``), as ``fuse`` reads each foot's single-foot run.
    reads_feet_alone: bool = False
    #: The fusion calibrates each foot's recording before fusing it (:meth:`foot_calibration`;
    #: its meta's ``"calibration"`` holds each foot's record).
    calibrates_feet: bool = False

    def foot_calibration(self, imu: ImuData, stance: StanceResult, foot: str) -> Any:
        """The calibration (:class:`~footnav.nav.calibration.StandstillCalibration`, its
        accelerometer scale applied) the fusion gives a foot's recording before fusing it, from
        the foot's samples up to the end of its first stance and their ``stance``; None for none.
        Online mode applies it to the foot's samples from its filter's start on."""


@runtime_checkable
class FusionSession(Protocol):
    """A coupled fusion's own work on a joint filter whose samples arrive as a walk goes on.

    A fusion's ``session(estimator, start_s)`` returns one for the feet's common start
    ``start_s`` (s). Online mode (:mod:`footnav.pipeline.online_joint`) starts the joint filter
    with both feet ``step_width_m`` apart (as the fusion's offline run does); whenever more of
    both feet's samples are final it asks :meth:`known_until` how far the session's measurements
    are known and calls :meth:`advance` up to there; :meth:`finish` at the end. The fusion's
    offline ``fuse`` runs the same session once over the whole walk, so the two give the same
    numbers.
    """

    step_width_m: float
    #: s: the session reads the filter's per-sample outputs back to this long before the start
    #: of each foot's latest stance (online, a new segment keeps them).
    history_s: float

    def known_until(self, view: Any, final_s: float) -> float:
        """The latest time (s) up to which every measurement of the session is known when both
        feet's samples (``view``) are final up to ``final_s`` (s): online, the joint filter runs
        no further."""
        ...

    def advance(
        self,
        filt: JointFilter,
        until_s: float,
        landings: Sequence[NDArray[np.float64]],
        view: Any,
        *,
        stop_s: float | None = None,
    ) -> None:
        """Apply every measurement of the fusion at times <= ``until_s`` (s); ``landings`` are
        each foot's stance starts (s) that became known since the last call (after the foot's
        first stance), ``view`` the feet's times and stance in the filter's sample indexing
        (:class:`footnav.fusion.joint.FeetView`), and ``stop_s`` the feet's common end (s) once
        it is known (the last call)."""
        ...

    def finish(self) -> dict[str, Any]:
        """The fusion's meta (what it applied), after the last :meth:`advance`."""
        ...


class HeadingAid(Component):
    """Corrects the heading of a run's final trajectories: ``correct(result, left, right=None)``.

    ``result`` is the fusion's :class:`~footnav.core.types.FusionResult`, ``left`` / ``right`` the
    feet's :class:`~footnav.core.types.ImuData` (a magnetometer aid reads ``mag``); returns the
    corrected FusionResult, each corrected foot's ``meta["heading_aid"]`` saying what was done.
    The pipeline calls it after the fusion, before the height model. Online mode runs only the
    aids whose ``online`` is True.
    """

    kind: ClassVar[str] = "heading_aid"
    #: The aid can run on a live stream (it needs no later sample).
    online: ClassVar[bool] = False

    def correct(  # pragma: no cover
        self, result: FusionResult, left: ImuData, right: ImuData | None = None
    ) -> FusionResult:
        """The fusion's result with its heading corrected (see the class docstring).

        Parameters
        ----------
        result
            The fusion's :class:`~footnav.core.types.FusionResult`.
        left, right
            The feet's :class:`~footnav.core.types.ImuData`; ``right`` None for one foot.

        Returns
        -------
        FusionResult
            The corrected result; each foot's ``meta["heading_aid"]`` says what was done.
        """
        raise NotImplementedError


KINDS = {"detector": StanceDetector, "estimator": FootEstimator, "fusion": Fusion, "heading_aid": HeadingAid}
