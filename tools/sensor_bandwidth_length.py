"""Does a sensor's band limit shorten a ZUPT track? The simulator's walk at 1 kHz, read at 100 Hz.

A real IMU does not sample the instantaneous rates the simulator gives: its samples are averages
or low-passed values. This reads the simulator's noise-free straight walk (1000 Hz) as a 100 Hz
sensor would, by point sampling, a box-car mean over each interval, or a 2nd-order Butterworth
low-pass (causal, and zero-phase) at ``--cutoffs`` Hz, runs the default pipeline on each and
prints the walked length against the truth (``short`` > 0: the estimate is shorter, as on the
real recordings of docs/heading.md).

Usage::

    PYTHONPATH=$PWD python tools/sensor_bandwidth_length.py [--distance 100] [--cutoffs 50,25,10]
"""

from __future__ import annotations

import argparse
import warnings

import numpy as np
from scipy import signal

import footnav

HIGH_HZ, FACTOR = 1000.0, 10


def walked(t, acc, gyr) -> float:
    """The default pipeline's start-to-end horizontal distance (m) on these samples."""
    res = footnav.make_pipeline().run(footnav.ImuData(t=t, acc=acc, gyr=gyr))
    return float(np.linalg.norm(res.left.position[-1, :2] - res.left.position[0, :2]))


def readings(t, acc, gyr, cutoffs):
    """(label, t, acc, gyr) of each way of reading the 1 kHz signals at 100 Hz."""
    yield "point samples", t[::FACTOR], acc[::FACTOR], gyr[::FACTOR]
    n = (len(t) - 1) // FACTOR

    def box(x):
        return x[1 : 1 + n * FACTOR].reshape(n, FACTOR, 3).mean(axis=1)

    yield "box-car mean", t[FACTOR::FACTOR][:n] - 0.5 * (FACTOR - 1) / HIGH_HZ, box(acc), box(gyr)
    for fc in cutoffs:
        b, a = signal.butter(2, fc, fs=HIGH_HZ)
        sos = signal.butter(2, fc, fs=HIGH_HZ, output="sos")
        yield (
            f"Butterworth {fc:g} Hz",
            t[::FACTOR],
            signal.lfilter(b, a, acc, axis=0)[::FACTOR],
            signal.lfilter(b, a, gyr, axis=0)[::FACTOR],
        )
        yield (
            f"zero-phase Butterworth {fc:g} Hz",
            t[::FACTOR],
            signal.sosfiltfilt(sos, acc, axis=0)[::FACTOR],
            signal.sosfiltfilt(sos, gyr, axis=0)[::FACTOR],
        )


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--distance", type=float, default=100.0, help="straight walk, m")
    ap.add_argument("--cutoffs", default="50,25,10", help="low-pass cut-offs, Hz")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    rec = footnav.simulate("straight", rate_hz=HIGH_HZ, noise=False, distance_m=args.distance)
    truth = rec.truth_left.position
    true_m = float(np.linalg.norm(truth[-1, :2] - truth[0, :2]))
    imu = rec.left
    for label, t, acc, gyr in readings(imu.t, imu.acc, imu.gyr, [float(c) for c in args.cutoffs.split(",")]):
        est = walked(t, acc, gyr)
        print(f"{label:34s} truth {true_m:8.3f} m, estimate {est:8.3f} m, short {100 * (true_m / est - 1):+.2f} %")


if __name__ == "__main__":
    main()
