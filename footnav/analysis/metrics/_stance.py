"""Stance detection scores: steps found / missed / false ([Li2018] Table 1) against a stance mask,
one event per stance or labelled swings inside trial boundaries ([IPOL]), with precision, recall
and F1; per-sample scores of a stance mask. References in :mod:`footnav.analysis.metrics`."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import linear_sum_assignment

from footnav.analysis.metrics._checks import _events, _finite, _float64, _mask, _percent, _readonly, _same_length
from footnav.analysis.metrics._matching import EventMatches, match_events
from footnav.core.errors import InvalidInputError, InvalidParameterError
from footnav.core.types import stance_intervals


@dataclass(frozen=True, eq=False)
class StepDetection:
    """Steps found / missed / false, [Li2018] Table 1.

    Attributes
    ----------
    n_detected
        Detected stance phases ("Steps Number").
    n_reference
        Reference stance phases.
    n_found
        Detected stances matched one to one to a reference stance.
    n_missed
        Reference stances without a match ("Missing Number").
    n_false
        Detected stances without a match (extra detections).
    missed_percent
        ``100 n_missed / n_reference`` (nan if no reference stance).
    false_percent
        ``100 n_false / n_reference``, [Li2018]'s "(rate in %)": 6 / 729 = 0.823 %.
    matches
        The :class:`EventMatches` of the stance anchors (samples).
    """

    n_detected: int
    n_reference: int
    n_found: int
    n_missed: int
    n_false: int
    missed_percent: float
    false_percent: float
    matches: EventMatches

    # Short names of the three counts ("steps found / missed / false").
    @property
    def found(self) -> int:
        """Same as ``n_found``."""
        return self.n_found

    @property
    def missed(self) -> int:
        """Same as ``n_missed``."""
        return self.n_missed

    @property
    def false(self) -> int:
        """Same as ``n_false``."""
        return self.n_false

    @property
    def precision(self) -> float:
        """``n_found / n_detected``: the fraction of detected stances that are real (nan if none)."""
        return self.n_found / self.n_detected if self.n_detected else float("nan")

    @property
    def recall(self) -> float:
        """``n_found / n_reference``: the fraction of reference stances found (nan if none)."""
        return self.n_found / self.n_reference if self.n_reference else float("nan")

    @property
    def f1(self) -> float:
        """Step F1 = ``2 n_found / (n_detected + n_reference)`` (nan if both are 0).

        The harmonic mean of precision and recall, one number that penalises missed and false
        steps alike.
        """
        den = self.n_detected + self.n_reference
        return 2.0 * self.n_found / den if den else float("nan")


def _step_detection(m: EventMatches) -> StepDetection:
    """The counts of one-to-one matches: detected = matched + false, reference = matched + missed."""
    n_ref = len(m.matches) + len(m.missed)
    return StepDetection(
        len(m.matches) + len(m.false),
        n_ref,
        len(m.matches),
        len(m.missed),
        len(m.false),
        _percent(len(m.missed), n_ref),
        _percent(len(m.false), n_ref),
        m,
    )


def _anchors(mask: NDArray[np.bool_], anchor: str) -> NDArray[np.float64]:
    iv = stance_intervals(mask)
    if anchor == "center":
        # midpoint of the first and last stance sample
        return (iv[:, 0] + iv[:, 1] - 1) / 2.0
    return iv[:, 0].astype(np.float64)


def step_detection(
    detected_mask: ArrayLike,
    reference_mask: ArrayLike,
    *,
    tolerance_samples: float,
    anchor: Literal["center", "onset"] = "center",
) -> StepDetection:
    """Steps found / missed / false by matching stance phases ([Li2018] Table 1).

    Each run of True in a mask is one stance phase (one step of that foot). A stance is represented
    by its ``anchor``: ``"center"`` (default, midpoint of its first and last sample -- robust to
    detectors that start or end stances early or late, which move one edge only) or ``"onset"``
    (first sample). Detected and reference anchors are matched one to one with
    :func:`match_events` within ``tolerance_samples``. [Li2018] Table 1 reports "Steps Number",
    "Missing Number" and "False Negative (rate in %)"; its numbers (735 detected for 729 true
    steps, 0 missing, 6 = 0.823 % of 729) show the last column counts *extra* detections relative
    to the reference count, which is ``n_false`` / ``false_percent`` here.

    Parameters
    ----------
    detected_mask, reference_mask
        Per-sample stance masks (N,), same N.
    tolerance_samples
        Largest anchor distance for a match, samples (e.g. a quarter of a gait cycle).
    anchor
        ``"center"`` or ``"onset"``.
    """
    det = _mask(detected_mask, "detected_mask")
    ref = _mask(reference_mask, "reference_mask")
    _same_length(ref, det, "reference_mask", "detected_mask")
    if anchor not in ("center", "onset"):
        raise InvalidParameterError(f"anchor must be 'center' or 'onset', got {anchor!r}")
    m = match_events(_anchors(det, anchor), _anchors(ref, anchor), tolerance=tolerance_samples)
    return _step_detection(m)


def step_detection_from_events(
    detected_mask: ArrayLike, reference_events: ArrayLike, *, tolerance_samples: float = 0.0
) -> StepDetection:
    """Steps found / missed / false against one reference event per stance ([Li2018] Table 1).

    For references that mark each stance by one instant (mocap-derived mid-stance or foot-flat
    events) instead of a stance mask. A reference event is found when it lies inside a detected
    stance phase, widened by ``tolerance_samples`` on each side; each detected stance finds at most
    one event (one to one, :func:`match_events` on the nearest anchor inside the phase). Detected
    stances outside the span of the reference events (a standstill before the first labelled
    stride or after the last) are neither found nor false: the reference says nothing there.

    Parameters
    ----------
    detected_mask
        Per-sample stance mask (N,).
    reference_events
        Reference stance events as sample indices (K,).
    tolerance_samples
        Widening of each detected stance phase, samples.
    """
    det = _mask(detected_mask, "detected_mask")
    ref = np.sort(_events(reference_events, "reference_events").astype(np.float64))
    if tolerance_samples < 0:
        raise InvalidParameterError(f"tolerance_samples must be >= 0, got {tolerance_samples!r}")
    runs = stance_intervals(det)
    if len(ref):
        inside_span = (runs[:, 1] - 1 + tolerance_samples >= ref[0]) & (runs[:, 0] - tolerance_samples <= ref[-1])
        runs = runs[inside_span]
    # each stance phase takes the free reference event nearest its centre among those inside it;
    # phases are visited in time order, so a widened phase cannot take its neighbour's event twice
    pairs: list[tuple[int, int]] = []
    used_ref: set[int] = set()
    for j, (a, b) in enumerate(runs):
        hits = [
            i
            for i in np.flatnonzero((ref >= a - tolerance_samples) & (ref <= b - 1 + tolerance_samples))
            if i not in used_ref
        ]
        if hits:
            centre = 0.5 * (a + b - 1)
            r = int(min(hits, key=lambda i: abs(ref[i] - centre)))
            pairs.append((j, r))
            used_ref.add(r)
    used_det = {d for d, _ in pairs}
    matches = np.array([[0.5 * (runs[d, 0] + runs[d, 1] - 1), ref[r]] for d, r in pairs]).reshape(-1, 2)
    missed = np.array([ref[i] for i in range(len(ref)) if i not in used_ref])
    false = np.array([0.5 * (runs[j, 0] + runs[j, 1] - 1) for j in range(len(runs)) if j not in used_det])
    # every kept run is matched or false, every reference event matched or missed
    return _step_detection(EventMatches(matches, missed, false))


def _swing_pairs(value: ArrayLike, n: int) -> NDArray[np.int64]:
    arr = _float64(value, "swings")
    if arr.size == 0:
        return np.empty((0, 2), dtype=np.int64)
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise InvalidInputError(
            f"expected (K, 2) [toe_off, heel_strike] sample indices, got {arr.shape}", field="swings"
        )
    _finite(arr, "swings")
    bad = (arr != np.round(arr)).any(axis=1) | (arr < 0).any(axis=1) | (arr > n).any(axis=1) | (arr[:, 0] >= arr[:, 1])
    if bad.any():
        i = int(np.argmax(bad))
        raise InvalidInputError(
            f"swing {arr[i].tolist()} is not [toe_off, heel_strike] with 0 <= toe_off < heel_strike <= {n}",
            field="swings",
            index=i,
        )
    return arr.astype(np.int64)


def _match_inside(anchors: NDArray[np.float64], ref_runs: NDArray[np.int64], tol: float) -> EventMatches:
    """One-to-one matching of detected anchors to reference runs [a, b) that contain them (+- tol)."""
    centres = (ref_runs[:, 0] + ref_runs[:, 1] - 1) / 2.0 if len(ref_runs) else np.empty(0)
    pairs: list[tuple[int, int]] = []
    if len(anchors) and len(ref_runs):
        allowed = (anchors[:, None] >= ref_runs[None, :, 0] - tol) & (
            anchors[:, None] <= ref_runs[None, :, 1] - 1 + tol
        )
        cost = np.abs(anchors[:, None] - centres[None, :])
        # a forbidden pair costs more than any set of allowed ones: most pairs first, then closest
        big = (float(cost.max()) + 1.0) * (min(cost.shape) + 1)
        rows, cols = linear_sum_assignment(np.where(allowed, cost, big))
        pairs = [(int(r), int(c)) for r, c in zip(rows, cols) if allowed[r, c]]
    pairs.sort(key=lambda rc: rc[1])
    used_d = {r for r, _ in pairs}
    used_r = {c for _, c in pairs}
    matches = np.array([[anchors[r], centres[c]] for r, c in pairs], dtype=np.float64).reshape(-1, 2)
    missed = np.array([centres[j] for j in range(len(centres)) if j not in used_r], dtype=np.float64)
    false = np.array([anchors[i] for i in range(len(anchors)) if i not in used_d], dtype=np.float64)
    return EventMatches(_readonly(matches), _readonly(missed), _readonly(false))


def step_detection_from_swings(
    detected_mask: ArrayLike,
    swings: ArrayLike,
    boundaries: tuple[int, int] | ArrayLike,
    *,
    tolerance_samples: float,
    anchor: Literal["center", "onset"] = "center",
) -> StepDetection:
    """Steps found / missed / false against labelled swings inside trial boundaries ([IPOL], [Li2018]).

    For references that label each SWING of a foot (toe-off, heel strike) and only inside the
    trial's boundaries, as [IPOL] does (hand-checked; steps after the trial's end and the
    standing before its start are not labelled).

    * Swing k covers samples ``toe_off_k <= i < heel_strike_k``; the labelled span is
      ``start <= i < end`` (``boundaries``, half-open: [IPOL]'s end boundary is the last heel
      strike, so the span ends as the last swing ends).
    * Reference stance phases are the runs of labelled, non-swing samples: the gaps between
      consecutive swings (heel strike k to toe-off k + 1), and also the standing still before
      the foot's first swing and after its last swing, as far as they lie inside the span. The
      foot does stand there (the walk starts and ends standing), so those are stances; [IPOL]'s
      start boundary is a toe-off, so the foot that starts walking has no leading stance in the
      span while the other foot has a partial one (from the start boundary to its first toe-off).
    * Detected stances are clipped to the span: a detected stance outside it is neither found
      nor false; one that straddles a boundary counts by its inside part. An inside part of at
      most ``tolerance_samples`` samples that touches the span's edge is dropped: it is a
      detection ending (or starting) a few samples past a boundary that coincides with a
      labelled swing's edge, timing jitter within the tolerance, not a stance.
    * A detected stance (represented by its ``anchor``) is found when the anchor lies inside a
      reference stance widened by ``tolerance_samples`` on each side, one to one (a reference
      stance split in two by a detector finds one; the other is false). Inside, not near the
      reference's centre: the reference stance runs from heel strike to toe-off, the whole
      ground contact, while a zero-velocity detector finds its still middle, usually shifted
      toward heel-off (on IPOL trial 1-1, 10-15 samples from the reference centre). Among the
      admissible one-to-one pairings the one with most pairs, then the smallest summed distance
      of anchors to reference centres, is taken (linear sum assignment, as :func:`match_events`).

    Parameters
    ----------
    detected_mask
        Per-sample stance mask (N,) of the foot.
    swings
        (K, 2) labelled swings ``[toe_off, heel_strike]`` as sample indices of the same foot
        (``FootTruth.events["toe_off"]`` / ``["heel_strike"]``), in time order; swings outside
        the span are allowed (they only end reference stances).
    boundaries
        ``(start, end)`` sample indices of the labelled span, half-open
        (``FootTruth.meta["trial_boundaries"]`` of :func:`footnav.data.io.read_ipol`).
    tolerance_samples
        Widening of each reference stance, samples; also the longest boundary sliver dropped.
    anchor
        ``"center"`` (default) or ``"onset"`` of each (clipped) detected stance run.

    Returns
    -------
    StepDetection
        Counts inside the span; ``precision``, ``recall`` and ``f1`` as properties;
        ``matches`` holds ``[detected anchor, reference stance centre]`` pairs, the missed
        reference centres and the false detected anchors.
    """
    det = _mask(detected_mask, "detected_mask")
    n = len(det)
    sw = _swing_pairs(swings, n)
    b = _float64(boundaries, "boundaries").reshape(-1)
    if len(b) != 2 or not np.isfinite(b).all() or (b != np.round(b)).any() or not 0 <= b[0] < b[1] <= n:
        raise InvalidInputError(
            f"expected (start, end) sample indices with 0 <= start < end <= {n}, got {b.tolist()}", field="boundaries"
        )
    start, end = int(b[0]), int(b[1])
    tol = float(tolerance_samples)
    if not np.isfinite(tol) or tol < 0:
        raise InvalidParameterError(f"tolerance_samples must be >= 0, got {tolerance_samples!r}")
    if anchor not in ("center", "onset"):
        raise InvalidParameterError(f"anchor must be 'center' or 'onset', got {anchor!r}")
    labelled = np.zeros(n, dtype=bool)
    labelled[start:end] = True
    ref = labelled.copy()
    for a, z in sw:
        ref[a:z] = False
    runs = stance_intervals(det)
    clipped = np.column_stack((np.maximum(runs[:, 0], start), np.minimum(runs[:, 1], end))) if len(runs) else runs
    keep = clipped[:, 1] > clipped[:, 0] if len(runs) else np.zeros(0, dtype=bool)
    # boundary slivers: clipped at an edge and no longer than the timing tolerance
    at_edge = (runs[:, 0] < start) | (runs[:, 1] > end) if len(runs) else keep
    keep &= ~(at_edge & (clipped[:, 1] - clipped[:, 0] <= tol))
    det_in = np.zeros(n, dtype=bool)
    for a, z in clipped[keep]:
        det_in[a:z] = True
    # runs of det_in are the kept runs: clipped runs of one mask never touch each other
    m = _match_inside(_anchors(det_in, anchor), stance_intervals(ref), tol)
    return _step_detection(m)


@dataclass(frozen=True)
class SampleScores:
    """Per-sample classification scores of a stance mask (stance = positive class).

    Precision, recall, F1 and accuracy are fractions in [0, 1]; nan where the denominator is 0.
    """

    precision: float
    recall: float
    f1: float
    accuracy: float
    n_true_positive: int
    n_false_positive: int
    n_false_negative: int
    n_true_negative: int


def sample_scores(detected_mask: ArrayLike, reference_mask: ArrayLike) -> SampleScores:
    """Per-sample precision, recall, F1 and accuracy of a stance mask against a reference mask.

    ``precision = TP / (TP + FP)``, ``recall = TP / (TP + FN)``,
    ``F1 = 2 TP / (2 TP + FP + FN)``, ``accuracy = (TP + TN) / N``, stance (True) being the
    positive class. Not in the seed papers (which count steps, :func:`step_detection`); the
    standard per-sample complement.

    Parameters
    ----------
    detected_mask, reference_mask
        Per-sample stance masks (N,), same N, bool or 0/1.
    """
    det = _mask(detected_mask, "detected_mask")
    ref = _mask(reference_mask, "reference_mask")
    _same_length(ref, det, "reference_mask", "detected_mask")
    tp = int(np.sum(det & ref))
    fp = int(np.sum(det & ~ref))
    fn = int(np.sum(~det & ref))
    tn = int(np.sum(~det & ~ref))

    def ratio(num: int, den: int) -> float:
        return num / den if den else float("nan")

    return SampleScores(
        precision=ratio(tp, tp + fp),
        recall=ratio(tp, tp + fn),
        f1=ratio(2 * tp, 2 * tp + fp + fn),
        accuracy=ratio(tp + tn, len(det)),
        n_true_positive=tp,
        n_false_positive=fp,
        n_false_negative=fn,
        n_true_negative=tn,
    )
