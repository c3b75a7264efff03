"""The result of a pipeline run: both feet, the pedestrian path, the stances and provenance.

It lives with the pipeline (not with the bottom layer's data types) because its gait-parameter
view, :meth:`PipelineResult.strides`, uses :mod:`footnav.nav.strides`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from footnav.core.types import FootTrajectory, Path, StanceResult
from footnav.nav.strides import stride_parameters

__all__ = ["PipelineResult"]


@dataclass(frozen=True, eq=False)
class PipelineResult:
    """Everything a pipeline run produced, with its provenance.

    ``meta`` holds ``"pipeline"`` (the configuration, re-runnable with ``make_pipeline(**...)``),
    ``"footnav_version"``, ``"warnings"`` (the warnings :func:`footnav.warn` issued during this
    run), ``"stance_check"`` (each foot's stances against its gait cycles), ``"vertical_check"``
    (each foot's height trend over its level strides), ``"fusion"`` (what the
    fusion computed: its update counts, fitted values and suspended intervals, the feet's common
    span), ``"runtime_s"`` and ``"input"`` (the inputs' own meta).
    """

    left: FootTrajectory
    right: FootTrajectory | None
    path: Path
    stance_left: StanceResult
    stance_right: StanceResult | None
    meta: Mapping[str, Any] = field(default_factory=dict)

    def _feet(self) -> list[tuple[str, FootTrajectory, StanceResult]]:
        feet = [("left", self.left, self.stance_left)]
        if self.right is not None and self.stance_right is not None:
            feet.append(("right", self.right, self.stance_right))
        return feet

    def strides(self) -> Any:
        """Gait parameters per stride and foot (:func:`footnav.nav.strides.stride_parameters`).

        A stride runs from one mid-stance to the next of the same foot (gaitmap's definition);
        columns :data:`footnav.nav.strides.STRIDE_COLUMNS` (SI units in the names), left foot's
        strides first, each foot's in time order. ``first``, ``last`` and ``standstill`` mark the
        strides that hold a pause, ``turn_deg`` the turns and ``kind`` the stairs: leave them out
        to average steady-state gait.

        Returns
        -------
        pandas.DataFrame
            One row per stride.

        Examples
        --------
        >>> res = footnav.make_pipeline().run(left, right)          # doctest: +SKIP
        >>> df = res.strides()                                        # doctest: +SKIP
        >>> steady = df[~df["first"] & ~df["last"] & ~df["standstill"] & (df["turn_deg"].abs() < 20)
        ...             & (df["kind"] == "level")]                      # doctest: +SKIP
        >>> steady.groupby("foot")[["length_m", "cadence_spm"]].mean()  # doctest: +SKIP
        """
        import pandas as pd  # here, not at module level: ``import footnav`` stays light

        table = np.concatenate([stride_parameters(tr, st, foot=foot) for foot, tr, st in self._feet()])
        return pd.DataFrame({name: table[name] for name in table.dtype.names})

    def to_dataframe(self) -> Any:
        """Per-sample trajectories of both feet as one long pandas DataFrame.

        Columns ``foot, t_s, pos_x_m, pos_y_m, pos_z_m, vel_x_mps, vel_y_mps, vel_z_mps, q_w, q_x,
        q_y, q_z, pos_std_x_m, pos_std_y_m, pos_std_z_m, stance`` (nav frame, z up; the columns of
        ``left.csv`` written by :func:`footnav.data.results.write_results`), left foot first.

        """
        import pandas as pd  # a core dependency, imported here so that ``import footnav`` stays light

        frames = []
        for foot, tr, st in self._feet():
            cols: dict[str, Any] = {"foot": np.full(len(tr.t), foot), "t_s": tr.t}
            for name, arr, axes, unit in (
                ("pos", tr.position, "xyz", "m"),
                ("vel", tr.velocity, "xyz", "mps"),
                ("q", tr.quaternion, "wxyz", ""),
                ("pos_std", tr.position_std, "xyz", "m"),
            ):
                for j, ax in enumerate(axes):
                    cols[f"{name}_{ax}_{unit}" if unit else f"{name}_{ax}"] = arr[:, j]
            cols["stance"] = np.asarray(st.mask, dtype=bool)
            frames.append(pd.DataFrame(cols))
        return pd.concat(frames, ignore_index=True)
