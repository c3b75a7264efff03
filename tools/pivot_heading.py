"""The default pipeline's heading through U-turns and pivoting stances, on the simulator.

A hallway walk of 8 legs of 20 m joined by 180-deg turns, at a turn radius of 1.5 m (a walked
U-turn) and 0.3 m (a turn of a few steps on the spot), each walking stance turned by
``stance_twist_deg`` about the vertical (0, 5, 10, 20 deg; the next swing turns it back), seeds
0-2 with the default sensor: the left foot's 2-D ATE (mean / worst), its heading error at the
end (mean of |.|, after removing the start's), and the stances detected against the truth's.

Usage::

    PYTHONPATH=$PWD python tools/pivot_heading.py [--pipeline JSON]
"""

from __future__ import annotations

import argparse
import json
import warnings

import numpy as np

import footnav
from footnav.analysis import metrics

HALL = [(20.0, 180.0)] * 8


def _yaw(q: np.ndarray) -> np.ndarray:
    return np.arctan2(2 * (q[:, 0] * q[:, 3] + q[:, 1] * q[:, 2]), 1 - 2 * (q[:, 2] ** 2 + q[:, 3] ** 2))


def _starts(mask) -> int:
    return int(np.sum(np.diff(np.asarray(mask, dtype=int)) == 1))


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pipeline", default="{}", help="make_pipeline keywords as JSON")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    pipe = footnav.make_pipeline(**json.loads(args.pipeline))
    for radius in (1.5, 0.3):
        for twist in (0.0, 5.0, 10.0, 20.0):
            rows = []
            for seed in range(3):
                rec = footnav.simulate("path", seed=seed, segments=HALL, turn_radius_m=radius, stance_twist_deg=twist)
                res = pipe.run(rec.left, rec.right)
                err = np.angle(np.exp(1j * (_yaw(res.left.quaternion) - _yaw(rec.truth_left.quaternion))))
                err -= err[:200].mean()
                rows.append(
                    (
                        metrics.ate_rmse(res.left.position, rec.truth_left.position, dims=2),
                        np.degrees(abs(err[-1])),
                        _starts(rec.truth_left.stance),
                        _starts(res.stance_left.mask),
                    )
                )
            r = np.array(rows)
            print(
                f"turn radius {radius} m, stance twist {twist:4.1f} deg: ATE {r[:, 0].mean():.3f} / "
                f"{r[:, 0].max():.3f} m, end heading error {r[:, 1].mean():.2f} deg, stances "
                f"{int(r[:, 3].sum())} detected of {int(r[:, 2].sum())}"
            )


if __name__ == "__main__":
    main()
