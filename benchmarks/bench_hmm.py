"""HMM detector speed: fit (K-means + re-ordering + Baum-Welch) and detect on a long simulated walk.

Run:  python benchmarks/bench_hmm.py [--minutes 10] [--rate-hz 100] [--repeat 3]

Prints the machine, the recording, the best-of-``repeat`` wall time of ``HmmDetector.fit`` (the
target: under 5 s for 10 minutes at 100 Hz), of ``detect`` with the fitted model (Viterbi +
forward-backward, no refit) and of ``detect`` on an unfitted detector (fit + decode), with the EM
iterations and whether EM converged.
"""

from __future__ import annotations

import argparse
import os
import platform

import numpy as np
from _common import best_of, cpu_name, straight_walk  # benchmarks/_common.py (scripts run from benchmarks/)

#: The brief's budget for fitting 10 minutes of 100 Hz data, s.
FIT_BUDGET_S = 5.0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--minutes", type=float, default=10.0)
    ap.add_argument("--rate-hz", type=float, default=100.0)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()

    import hmmlearn
    import sklearn

    from footnav.detectors.hmm import HmmDetector

    rec = straight_walk(args.minutes, args.rate_hz)
    imu = rec.left

    def best(fn) -> tuple[float, object]:
        return best_of(fn, args.repeat)

    fit_s, det = best(lambda: HmmDetector(seed=0).fit(imu))
    detect_s, _ = best(lambda: det.detect(imu))
    fresh_s, _ = best(lambda: HmmDetector(seed=0).detect(imu))
    info = det.fit_info_

    print(
        f"machine: {platform.machine()}, {cpu_name()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
        f"numpy {np.__version__}, scikit-learn {sklearn.__version__}, hmmlearn {hmmlearn.__version__}"
    )
    print(
        f"recording: {imu.duration_s / 60:.1f} min simulated at {args.rate_hz:g} Hz, {imu.n_samples} samples, "
        f"model rate {det.model_rate_hz_:g} Hz ({info['n_samples']} samples)"
    )
    print(
        f"fit:                 {fit_s:.2f} s  (best of {args.repeat}; EM {info['n_iter']} iterations, "
        f"converged={info['converged']}; budget {FIT_BUDGET_S:g} s: {'OK' if fit_s < FIT_BUDGET_S else 'OVER'})"
    )
    print(f"detect, fitted:      {detect_s:.2f} s  (Viterbi + forward-backward, no refit)")
    print(f"detect, unfitted:    {fresh_s:.2f} s  (fit on the recording + decode)")


if __name__ == "__main__":
    main()
