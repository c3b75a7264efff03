"""Replaying a recording through an online stream, for the online tests (tests/pipeline/test_online*.py)."""

from __future__ import annotations

import warnings

import numpy as np

import footnav

#: Step-wise smoothing: the offline run the online one must reproduce.
STEP = {"smoother": "step"}


def _chunks(imu, size):
    """The samples in chunks of ``size``, or of the sizes of a tuple ``size`` in turn."""
    sizes = size if isinstance(size, tuple) else (size,)
    a, i = 0, 0
    while a < imu.n_samples:
        b = a + sizes[i % len(sizes)]
        yield imu.t[a:b], imu.acc[a:b], imu.gyr[a:b]
        a, i = b, i + 1


def _replay(pipe, left, right, size_left, size_right=None, **options):
    """Push the recording in chunks, each foot's next chunk when it is the earlier one (on the
    common clock); returns the positions returned per foot, the steps, the close() result and
    the stream."""
    stream = pipe.online(feet=1 if right is None else 2, **options)
    offsets = options.get("clock_offset_s", {})
    clocks = options.get("clocks", {})

    def common(foot, t):  # a chunk's first time on the common clock
        return float(clocks[foot](t)) if foot in clocks else t + offsets.get(foot, 0.0)

    got = {"left": [], "right": []}
    steps = []
    queues = {"left": _chunks(left, size_left)}
    if right is not None:
        queues["right"] = _chunks(right, size_right or size_left)
    heads = {foot: next(q, None) for foot, q in queues.items()}
    while any(h is not None for h in heads.values()):
        foot = min((f for f, h in heads.items() if h is not None), key=lambda f: common(f, heads[f][0][0]))
        update = stream.push(**{foot: heads[foot]})
        heads[foot] = next(queues[foot], None)
        for name, positions in got.items():
            fu = getattr(update, name)
            if fu is not None:
                positions.append(fu.position)
        steps += update.steps
    result = stream.close()
    for name, positions in got.items():
        fu = getattr(stream.last_update, name)
        if fu is not None:
            positions.append(fu.position)
    steps += stream.last_update.steps
    return {k: np.concatenate(v) for k, v in got.items() if v}, steps, result, stream


def _check_equal(off, got, result, feet=("left", "right")):
    for foot in feet:
        ref = getattr(off, foot)
        pos = got[foot]
        assert pos.shape == ref.position.shape
        # every step end (last stance sample) and every sample, to 1e-9 m
        ends = ref.steps[:, 1] - 1
        np.testing.assert_allclose(pos[ends], ref.position[ends], atol=1e-9, rtol=0)
        np.testing.assert_allclose(pos, ref.position, atol=1e-9, rtol=0)
        np.testing.assert_allclose(getattr(result, foot).position, ref.position, atol=1e-9, rtol=0)
        np.testing.assert_allclose(getattr(result, foot).position_std, ref.position_std, atol=1e-9, rtol=0)
        np.testing.assert_array_equal(getattr(result, f"stance_{foot}").mask, getattr(off, f"stance_{foot}").mask)


def shared_recordings(shared_data, names):
    """The shared recordings of ``names`` that are present (loaded quietly), in order."""
    from footnav.data.datasets import load_dataset

    for name in names:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                yield load_dataset(name, shared_data)
        except footnav.DataNotFoundError:
            continue
