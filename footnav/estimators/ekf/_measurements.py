"""The measurements of :class:`~footnav.estimators.ekf.filter.InsFilter` from outside its ZUPT:
a caller's linear update of the joint error state (a dense Kalman update, kept for the smoothers
at a checkpoint of its instant), and the range constraint's, which the compiled loop applies
itself while it runs (:func:`footnav.estimators.ekf._loop.run`'s watch).

:class:`Measurements` is a base of ``InsFilter``; it reads the filter's state and records and
calls its loop (``_run``), so it is not used alone.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import InvalidInputError
from footnav.estimators.ekf._kernels import feedback_all
from footnav.estimators.ekf._loop import APART, NOT_PD, Watch
from footnav.estimators.ekf._records import CallerUpdate, empty_log
from footnav.nav.kalman import DENSE_BAD_INPUT, DENSE_NOT_PD, update_dense

if TYPE_CHECKING:
    from footnav.estimators.ekf._records import Checkpoint, FilterState, UpdateLog, Work

__all__ = ["Measurements", "loop_watch"]


def loop_watch(
    times: NDArray[np.float64], bound_m: float = 0.0, var_m2: float = 0.0, symmetric: bool = False, start: int = 0
) -> Watch:
    """The loop's :class:`~footnav.estimators.ekf._loop.Watch` (typed alike for every call: one
    compilation)."""
    return Watch(
        times,
        float(bound_m),
        float(var_m2),
        bool(symmetric),
        np.array([start], dtype=np.int64),
        np.zeros(1, dtype=np.int64),
    )


class Measurements:
    """A caller's updates (:meth:`update`, :meth:`update_position`) and the range constraint's
    runs (:meth:`run_until_apart`, :meth:`run_range_constrained`) of an ``InsFilter``."""

    if TYPE_CHECKING:  # what this base reads and calls of InsFilter (set and defined there)
        n_feet: int
        n_states: int
        _q: NDArray[np.float64]
        _v: NDArray[np.float64]
        _p: NDArray[np.float64]
        _ba: NDArray[np.float64]
        _bg: NDArray[np.float64]
        _cov: NDArray[np.float64]
        _state: FilterState
        _work: Work
        _dense: dict[int, tuple]
        _since_checkpoint: int
        _log: UpdateLog
        _n_log: int
        checkpoints: list[Checkpoint]
        step_smoother: Any  # smoother.py's, which imports filter.py
        segment_records: Any

        def block(self, foot: int, name: str) -> slice: ...

        def _add_checkpoint(self, step_end: bool, state: bool = True, full: bool = False) -> None: ...

        def _run(self, t_stop: float, watch: Watch | None) -> int: ...

    def update(
        self,
        h: NDArray[np.float64],
        innovation: NDArray[np.float64],
        r: float | NDArray[np.float64],
        *,
        gate: float | None = None,
    ) -> NDArray[np.float64] | None:
        """Linear measurement of the error state: ``innovation = h(x^) - z = H dx + noise``.

        Parameters
        ----------
        h
            H, (m, N) over the joint error state (see :meth:`block` for the columns).
        innovation
            h(x^) - z, (m,), in the measurement's units.
        r
            Measurement noise variance per component, (m,) or scalar, units squared.
        gate
            If given, skip the update (return None) when the normalised innovation squared
            y' S^-1 y exceeds it (a chi-square gate against outliers).

        Returns
        -------
        ndarray or None
            The correction dx that was fed back into the nominal states (and recorded for the
            smoother), or None when the gate rejected the measurement.
        """
        big = self._cov.shape[0]
        # C-contiguous float64 (one compiled signature of update_dense)
        hm = np.ascontiguousarray(np.atleast_2d(np.asarray(h, dtype=np.float64)))
        y = np.ascontiguousarray(np.atleast_1d(np.asarray(innovation, dtype=np.float64)))
        m = len(y)
        r = np.asarray(r, dtype=np.float64)
        if r.shape != (m,):
            r = np.full(m, float(r)) if r.size == 1 else r
        if hm.shape != (m, big) or r.shape != (m,) or y.ndim != 1:
            raise InvalidInputError(
                f"measurement update needs H of shape ({m}, {big}), {m} innovations and {m} variances (or one); "
                f"got H {hm.shape}, innovation {y.shape}, r {r.shape}",
                field="innovation",
            )
        r = np.ascontiguousarray(r)
        if m not in self._dense:  # scratch by rows: Cholesky factor and P H'
            self._dense[m] = (np.zeros((m, m)), np.empty((big, m)), np.empty((big, big)))
        chol, ph, cov = self._dense[m]
        gain, sy, dx = np.empty((big, m)), np.empty(m), np.empty(big)  # kept by the checkpoint
        status, nis = update_dense(self._cov, hm, y, r, chol, ph, gain, sy, dx, cov)
        if status == DENSE_BAD_INPUT:
            raise InvalidInputError(
                "measurement update needs finite H and innovations and positive variances; "
                f"got innovation {y!r}, r {r!r}",
                field="innovation",
            )
        if status == DENSE_NOT_PD:
            raise InvalidInputError("measurement update: innovation covariance is not positive definite", field="r")
        if gate is not None and nis > gate:
            return None
        # the update belongs to a checkpoint at this instant, made before P changes (a kept
        # segment's backward pass starts from the covariance after its last sample); its state
        # is the one after the update, set below
        if self._since_checkpoint:
            self._add_checkpoint(step_end=False, state=False)
        self._cov[:] = cov
        self._apply(dx)
        cp = self.checkpoints[-1]
        cp.updates.append(CallerUpdate(hm, gain, sy, y))
        # the checkpoint holds the state after every update at this instant
        cp.state = self._state.copy()
        if self.step_smoother is not None:
            self.step_smoother.add_update(self, hm, gain, sy, y)
        if self.segment_records is not None:
            self.segment_records.add_update(len(self.checkpoints) - 1, hm, gain, sy, y, self._cov)
        return dx

    def selection(self, indices: NDArray[np.int64]) -> NDArray[np.float64]:
        """H that measures the error states ``indices`` (one row each)."""
        idx = np.asarray(indices, dtype=np.int64)
        h = np.zeros((len(idx), self._cov.shape[0]))
        h[np.arange(len(idx)), idx] = 1.0
        return h

    def update_position(
        self, foot: int, z: NDArray[np.float64], std_m: float | NDArray[np.float64], axes: int = 3
    ) -> NDArray[np.float64] | None:
        """Position measurement ``z`` (m, nav) of ``foot``'s first ``axes`` axes (2: horizontal)."""
        sl = self.block(foot, "pos")
        h = self.selection(np.arange(sl.start, sl.start + axes))
        innov = self._p[foot, :axes] - np.asarray(z, float)[:axes]
        var = np.asarray(std_m, float) ** 2
        return self.update(h, innov, np.full(axes, float(var)) if var.ndim == 0 else var)

    def _apply(self, dx: NDArray[np.float64]) -> None:
        feedback_all(self._q, self._v, self._p, self._ba, self._bg, dx, self.n_states, self._work.dq, self._work.q_tmp)

    def run_until_apart(self, times: NDArray[np.float64], bound_m: float, start: int = 0) -> int | None:
        """Run through ``times`` (s, increasing) from index ``start`` until the two feet are more
        than ``bound_m`` apart at one of them.

        At each time the check sees the filter as :meth:`run_until` of that time leaves it, so
        this equals ``run_until(t)`` and a distance check for each ``t`` in turn, without a return
        to Python at each (a range constraint checks every 0.05 s).

        Returns
        -------
        int or None
            The index of the first time at which the feet are farther apart than ``bound_m`` (or
            their distance is not a number), the filter standing at it; None when there is none,
            the filter standing at the last time.
        """
        if self.n_feet != 2:
            raise ValueError("run_until_apart needs a filter of two feet")
        times = np.ascontiguousarray(times, dtype=np.float64)
        if start >= len(times):
            return None
        watch = loop_watch(times, bound_m, start=start)  # no projection (variance 0): stop
        if self._run(float(times[-1]), watch) == APART:
            return int(watch.index[0])
        return None

    def run_range_constrained(
        self, times: NDArray[np.float64], bound_m: float, std_m: float, symmetric: bool = False, start: int = 0
    ) -> tuple[int | None, int]:
        """Run through ``times`` (s, increasing) from index ``start``, enforcing a range
        constraint at each: where the feet are more than ``bound_m`` apart, their positions are
        measured on the bound (std ``std_m`` per axis, m) inside the compiled loop.

        The projection is the ``range`` fusion's (:class:`footnav.fusion.range_constraint.RangeSession`):
        the moving foot onto the sphere around the standing one (``symmetric=False``, one foot
        standing), else both feet about their centroid. Each measurement is fed back into both
        feet and kept for the smoothers like the filter's own updates; a replay from a
        checkpoint applies it again (:class:`~footnav.estimators.ekf._records.UpdateLog`), so the
        run needs no checkpoint at each, and no return to Python.

        Returns
        -------
        tuple of (int or None, int)
            The index of a time at which the feet's distance is not a number (the filter standing
            at it, nothing applied there; the caller's to report), or None when every time is
            done; and the number of times at which the constraint was applied.

        Raises
        ------
        InvalidInputError
            When a projection's innovation covariance is not positive definite.
        """
        if self.n_feet != 2:
            raise ValueError("run_range_constrained needs a filter of two feet")
        if not std_m > 0:
            raise InvalidInputError(f"run_range_constrained needs std_m > 0; got {std_m!r}", field="std_m")
        times = np.ascontiguousarray(times, dtype=np.float64)
        if start >= len(times):
            return None, 0
        room = self._n_log + 2 * (len(times) - start)  # at most two measurements per time
        if len(self._log.event) < room:
            grown = empty_log(max(room, 2 * len(self._log.event)))
            for old, new in zip(self._log, grown):
                new[: self._n_log] = old[: self._n_log]
            self._log = grown
        watch = loop_watch(times, bound_m, float(std_m) ** 2, symmetric, start)
        reason = self._run(float(times[-1]), watch)
        if reason == NOT_PD:
            raise InvalidInputError("range constraint: innovation covariance is not positive definite", field="std_m")
        return (int(watch.index[0]) if reason == APART else None), int(watch.applied[0])
