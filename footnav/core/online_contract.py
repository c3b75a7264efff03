"""The online contract: what a stream (:mod:`footnav.pipeline.online`) needs of an estimator.

A pipeline runs online when its estimator is an :class:`OnlineEstimator`: its ``start`` gives an
:class:`OnlineFilter`, which the stream runs in bounded *segments*: it feeds the samples that
became final (``extend``), runs the filter as far as their stance decisions allow
(``run_until``), takes the samples up to each closed step (``checkpoints``, ``final_outputs``)
and, when a segment is full, starts the next with ``rebase``. Every sample index here is a foot's
own index in the segment, except a checkpoint's ``k`` (see :class:`OnlineFilter`). footnav's
``ekf`` is the reference implementation (:class:`footnav.estimators.ekf.OnlineInsFilter`);
``footnav.testing.OnlineEstimatorContract`` checks a candidate. The contracts of the offline
components are in :mod:`footnav.core.component`.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, Protocol, runtime_checkable

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

    from footnav.core.types import FootTrajectory, ImuData, StanceResult

__all__ = ["ONLINE_ESTIMATOR_MEMBERS", "ONLINE_FILTER_MEMBERS", "OnlineEstimator", "OnlineFilter", "online_gaps"]


@runtime_checkable
class OnlineFilter(Protocol):
    """A filter a stream runs in segments, one foot or two (0 left, 1 right); nav frame, SI units.

    Attributes
    ----------
    meta
        Per foot, the notes of its alignment (``FootTrajectory.meta`` takes them).
    checkpoints
        A list of the points the run stopped at since the segment began, the start first: each
        with ``k`` (per foot, the last processed sample as :meth:`global_index` numbers it) and
        ``step_end`` (a foot's stance ended there: its samples up to it are final). The stream
        may delete those it has read.
    """

    meta: list[dict]
    checkpoints: list[Any]

    def extend(
        self,
        t: NDArray[np.float64],
        acc: NDArray[np.float64],
        gyr: NDArray[np.float64],
        stance: NDArray[np.bool_],
        *,
        foot: int = 0,
    ) -> None:
        """Take ``foot``'s next samples (time s, specific force m/s^2, rate rad/s, stance)."""
        ...

    def run_until(self, t_stop: float = ...) -> None:
        """Process every foot's samples up to ``t_stop`` (s; all by default), in time order."""
        ...

    def capacity(self, foot: int) -> int:
        """Samples ``foot``'s segment has room for."""
        ...

    def samples(self, foot: int) -> Any:
        """``foot``'s samples given so far, a NamedTuple of arrays ``t``, ``acc``, ``gyr``,
        ``stance`` (views)."""
        ...

    def index(self, foot: int) -> int:
        """``foot``'s last processed sample."""
        ...

    def start_index(self, foot: int) -> int:
        """The sample ``foot``'s filter started at (its alignment's end)."""
        ...

    def global_index(self, foot: int, k: int) -> int:
        """The checkpoints' number of ``foot``'s sample ``k``."""
        ...

    def time(self, foot: int) -> float:
        """Time (s) of ``foot``'s last processed sample."""
        ...

    def position(self, foot: int) -> NDArray[np.float64]:
        """``foot``'s position now, (3,) m."""
        ...

    def velocity(self, foot: int) -> NDArray[np.float64]:
        """``foot``'s velocity now, (3,) m/s."""
        ...

    def quaternion(self, foot: int) -> NDArray[np.float64]:
        """``foot``'s attitude now, [w, x, y, z] body to nav."""
        ...

    @property
    def covariance(self) -> NDArray[np.float64]:
        """The error-state covariance now, (N, N)."""
        ...

    def block(self, foot: int, name: str) -> slice:
        """The error-state columns of ``foot``'s block ``name`` (at least ``"pos"``)."""
        ...

    def final_outputs(self, foot: int) -> Sequence[NDArray[np.float64]]:
        """``foot``'s per-sample attitude (K, 4), velocity (K, 3), position (K, 3) (smoothed
        per step where the filter smooths) and position covariance xx, xy, yy, zz (K, 4): final
        up to the last step-end checkpoint."""
        ...

    def open_step_start(self, foot: int) -> int | None:
        """The first sample of ``foot``'s step the smoother has not closed yet (None: none)."""
        ...

    def close_open_step(self) -> None:
        """Close the open step now (the stream's end): every processed sample is final."""
        ...

    def rebase(
        self,
        keep_from: Sequence[int],
        capacity: Sequence[int],
        *,
        at: int | None = None,
        step_smoother: bool | None = None,
    ) -> OnlineFilter:
        """The next segment, holding each foot's samples from ``keep_from[f]`` on (at most the
        sample before :meth:`open_step_start`), room for ``capacity[f]`` samples and a checkpoint
        at every step end. ``at`` None: it continues where this one stands, the open step and
        the kept samples' outputs carried over; ``at`` a checkpoint's index: it resumes there
        and the kept samples after it are run again. ``step_smoother``: smooth per step
        (default as this one)."""
        ...


@runtime_checkable
class OnlineEstimator(Protocol):
    """An estimator a stream runs: ``smoother`` is one of ``"none"``, ``"step"``, ``"whole"``
    (step-wise live, the whole walk's at close), ``heading`` ``"first-step"`` or another."""

    smoother: str
    heading: str

    def start(
        self,
        imus: Sequence[ImuData],
        stances: Sequence[StanceResult],
        *,
        initial_yaw_rad: Sequence[float] | None = None,
        initial_position_m: Sequence[NDArray[np.float64]] | None = None,
    ) -> OnlineFilter:
        """The filter over ``imus``, each foot aligned at its first stance, not yet run."""
        ...

    def package(
        self,
        t: NDArray[np.float64],
        q: NDArray[np.float64],
        vel: NDArray[np.float64],
        pos: NDArray[np.float64],
        pos_cov: NDArray[np.float64],
        start_index: int,
        filter_meta: dict,
        steps: NDArray[np.int64],
        *,
        smoothed: bool,
        heading: bool,
        biases: tuple | None = None,
    ) -> FootTrajectory:
        """A foot's trajectory from the stream's final samples, as ``estimate`` makes it."""
        ...

    def final_biases(self, filt: OnlineFilter, foot: int) -> tuple | None:
        """What ``package`` takes as ``biases`` (None: the estimator estimates none)."""
        ...

    def estimate(self, imu: ImuData, stance: StanceResult) -> FootTrajectory:
        """One foot offline (``close`` reruns it with the whole-walk smoother)."""
        ...

    def validate_params(self) -> None:
        """Raise InvalidParameterError for a parameter out of its range."""
        ...


#: The members of :class:`OnlineFilter` and :class:`OnlineEstimator`.
ONLINE_FILTER_MEMBERS = (
    "meta",
    "checkpoints",
    "extend",
    "run_until",
    "capacity",
    "samples",
    "index",
    "start_index",
    "global_index",
    "time",
    "position",
    "velocity",
    "quaternion",
    "covariance",
    "block",
    "final_outputs",
    "open_step_start",
    "close_open_step",
    "rebase",
)
ONLINE_ESTIMATOR_MEMBERS = ("smoother", "heading", "start", "package", "final_biases", "estimate", "validate_params")


def online_gaps(estimator: Any) -> list[str]:
    """The members of :class:`OnlineEstimator` ``estimator`` lacks (empty: it can run online;
    its filter is checked when ``start`` runs)."""
    return [m for m in ONLINE_ESTIMATOR_MEMBERS if not hasattr(estimator, m)]
