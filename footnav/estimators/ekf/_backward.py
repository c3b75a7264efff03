"""The compiled backward pass of the RTS smoother (Bryson-Frazier form) over a recorded run.

The mathematics is in :mod:`footnav.estimators.ekf.smoother`; this module holds what runs per
event of the filter's event log (:class:`~footnav.estimators.ekf._records.Record`, read by its
named fields and each event's ``kind``): the adjoint's transition ``mu <- F' mu``,
``d <- F^-1 d``, the step-wise smoother's chaining and the pass itself, which the forward loop
(:mod:`footnav.estimators.ekf._loop`) calls where a step or a segment ends, so that recording
and smoothing need no second compiled entry point. (The per-event work stays in the pass's body,
the log's arrays unpacked once: see :mod:`._loop` on helpers per sample.)
"""

from __future__ import annotations

from footnav._numba import njit  # numba.njit that survives a read-only install
from footnav.estimators.ekf._records import CALLER_UPDATE_ROWS, EV_CALLER_UPDATE, EV_SAMPLE
from footnav.nav.quaternion import from_rotvec_nb, multiply_nb, normalize_nb

__all__ = ["smooth_back"]


@njit(cache=True, inline="always", error_model="numpy")
def _ft_apply(mu, o, n, x, y, z, c, e, dt):
    """mu <- F' mu on one foot's block starting at ``o`` (``c[e]``: C of the transition)."""
    a0, a1, a2 = mu[o], mu[o + 1], mu[o + 2]
    v0, v1, v2 = mu[o + 3], mu[o + 4], mu[o + 5]
    # F' has S' = -S in the attitude row, dt I in the velocity row
    mu[o] = a0 + z * v1 - y * v2
    mu[o + 1] = a1 - z * v0 + x * v2
    mu[o + 2] = a2 + y * v0 - x * v1
    mu[o + 3] = v0 + dt * mu[o + 6]
    mu[o + 4] = v1 + dt * mu[o + 7]
    mu[o + 5] = v2 + dt * mu[o + 8]
    if n == 15:
        for j in range(3):
            mu[o + 9 + j] -= dt * (c[e, 0, j] * v0 + c[e, 1, j] * v1 + c[e, 2, j] * v2)
            mu[o + 12 + j] += dt * (c[e, 0, j] * a0 + c[e, 1, j] * a1 + c[e, 2, j] * a2)


@njit(cache=True, inline="always", error_model="numpy")
def _finv_apply(d, o, n, x, y, z, c, e, dt):
    """d <- F^-1 d on one foot's block starting at ``o``: F is unit block-triangular, so its
    inverse is back-substitution (attitude, then velocity, then position; biases unchanged)."""
    if n == 15:
        for i in range(3):
            d[o + i] -= dt * (c[e, i, 0] * d[o + 12] + c[e, i, 1] * d[o + 13] + c[e, i, 2] * d[o + 14])
            d[o + 3 + i] += dt * (c[e, i, 0] * d[o + 9] + c[e, i, 1] * d[o + 10] + c[e, i, 2] * d[o + 11])
    a0, a1, a2 = d[o], d[o + 1], d[o + 2]
    d[o + 3] -= -z * a1 + y * a2
    d[o + 4] -= z * a0 - x * a2
    d[o + 5] -= -y * a0 + x * a1
    d[o + 6] -= dt * d[o + 3]
    d[o + 7] -= dt * d[o + 4]
    d[o + 8] -= dt * d[o + 5]


@njit(cache=True, inline="always", error_model="numpy")
def _chain_steps(ev_foot, ev_k, ev_kind, used, n, n_feet, d, out_p, sm_p, offset, seen):
    """Each foot's smoothed positions of the step moved to start where its previous step's
    smoothing left it (``d``: P mu before the step; a foot's first sample in it follows its
    start sample)."""
    for f in range(n_feet):
        seen[f] = 0.0
    for e in range(used):
        f = ev_foot[e]
        if ev_kind[e] == EV_SAMPLE and seen[f] == 0.0:
            seen[f] = 1.0
            k0 = ev_k[e] - 1
            for i in range(3):
                offset[f, i] = d[f * n + 6 + i] + sm_p[k0, i] - out_p[k0, i]
    for e in range(used):
        if ev_kind[e] == EV_SAMPLE:
            f, k = ev_foot[e], ev_k[e]
            for i in range(3):
                sm_p[k, i] += offset[f, i]


@njit(cache=True, error_model="numpy")
# complexity: a compiled loop; split into helpers it ran slower (docs/changes.md, issue 38)
def smooth_back(  # noqa: C901
    fill,
    chain,
    cov,
    mu,
    d,
    n,
    n_feet,
    q_diag,
    clip_row,
    clip_q,
    rec,
    out_q,
    out_v,
    out_p,
    sm,
    kt,
    dq,
    q_tmp,
    offset,
    seen,
):
    """Bryson-Frazier backward pass over the recorded events ``fill[0] - 1`` down to 0 (and
    their ``fill[1]`` update rows) of the event log ``rec``
    (:class:`~footnav.estimators.ekf._records.Record`, read by its named fields and kinds).

    Each sample's smoothed output is its filtered output corrected by ``-d``, where ``d = P mu``
    is the smoothed minus the filtered error state. Going back through an update (K, y,
    S^-1 y): ``d <- d + K y``, ``mu <- mu + H' (S^-1 y - K' mu)``; through a transition:
    ``d <- F^-1 (d - Q mu)``, ``mu <- F' mu`` (from ``d = P mu``, P- = F P+ F' + Q and
    P+ = P- - K H P-). So no covariance is stored per sample.

    ``chain`` False (one segment of the whole-walk smoother): ``mu`` is the adjoint after the
    last event, and ``d = cov mu`` with ``cov`` the covariance there. ``chain`` True (one step
    of the step-wise smoother, OpenShoe's smoothed variant): mu = 0 at the step's end, and each
    foot's positions are chained to where its previous step's smoothing left it (position is
    an integral: the step's smoothed displacement is added to its smoothed start). On return,
    ``mu`` and ``d`` are those before the first event.

    ``out_q``, ``out_v``, ``out_p``: the filtered outputs (the arrays of
    :class:`~footnav.estimators.ekf._records.Outputs`); ``kt``,
    ``dq``, ``q_tmp``, ``offset``, ``seen``: those of :class:`~footnav.estimators.ekf._records.Work`. Those arrays,
    not the tuples: each array passed costs compilation (the unboxing wrapper numba makes for
    every kernel, and the copies of its fields), and this pass reads few of theirs.
    """
    # the arrays unpacked once, out of the loops: a tuple's field read in a loop costs numba a
    # reference count each time (measured: the loop 2x slower)
    ev_foot, ev_k, ev_fdt, ev_dt, ev_c, ev_kind, ev_width, ev_base, ev_gain, ev_sy, ev_y = rec
    sm_q, sm_v, sm_p = sm.q, sm.v, sm.p
    big = len(mu)
    used, row = fill[0], fill[1]
    for i in range(big):
        if chain:
            mu[i] = 0.0
            d[i] = 0.0
        else:
            acc = 0.0
            for j in range(big):
                acc += cov[i, j] * mu[j]
            d[i] = acc
    for e in range(used - 1, -1, -1):
        kind = ev_kind[e]
        o = ev_foot[e] * n
        k = ev_k[e]
        if kind == EV_SAMPLE:  # its smoothed output, then back through its updates and transition
            from_rotvec_nb(d[o], d[o + 1], d[o + 2], dq)
            multiply_nb(dq, out_q[k], q_tmp)
            normalize_nb(q_tmp)
            for i in range(4):
                sm_q[k, i] = q_tmp[i]
            for i in range(3):
                sm_v[k, i] = out_v[k, i] - d[o + 3 + i]
                sm_p[k, i] = out_p[k, i] - d[o + 6 + i]
        # its updates, last first (an event's update rows come before the next event's): 3-block
        # selections (a sample's ZUPT and ZARU, K in columns 3u:3u+3; the loop's own update), or
        # a caller's of m rows (K in columns 0:m of its first row, H' in those of its second)
        caller = kind == EV_CALLER_UPDATE
        m = ev_width[e] if caller else 3
        updates = 1 if caller else ev_width[e] // 3
        if caller:
            row -= CALLER_UPDATE_ROWS
        elif updates > 0:
            row -= 1
        for u in range(updates - 1, -1, -1):
            col = 3 * u
            for a in range(m):  # kt = S^-1 y - K' mu
                acc = ev_sy[row, col + a]
                for i in range(big):
                    acc -= ev_gain[row, i, col + a] * mu[i]
                kt[a] = acc
            for i in range(big):  # d <- d + K y
                acc = 0.0
                for a in range(m):
                    acc += ev_gain[row, i, col + a] * ev_y[row, col + a]
                d[i] += acc
            if caller:  # mu <- mu + H' kt
                for i in range(big):
                    acc = 0.0
                    for a in range(m):
                        acc += ev_gain[row + 1, i, a] * kt[a]
                    mu[i] += acc
            else:
                for a in range(m):
                    mu[ev_base[row, u] + a] += kt[a]
        if kind != EV_SAMPLE:
            continue
        # back through the sample's transition: d <- F^-1 (d - Q mu), mu <- F' mu
        dt = ev_dt[e]
        for i in range(n):
            d[o + i] -= q_diag[i] * dt * mu[o + i]
        j = clip_row[k]
        if j >= 0:  # a clipped sample's Q in nav (written by the forward loop)
            m0, m1, m2 = mu[o + 3], mu[o + 4], mu[o + 5]
            q = clip_q[j]
            d[o + 3] -= q[0] * m0 + q[1] * m1 + q[2] * m2
            d[o + 4] -= q[1] * m0 + q[3] * m1 + q[4] * m2
            d[o + 5] -= q[2] * m0 + q[4] * m1 + q[5] * m2
        x, y, z = ev_fdt[e, 0], ev_fdt[e, 1], ev_fdt[e, 2]
        _finv_apply(d, o, n, x, y, z, ev_c, e, dt)
        _ft_apply(mu, o, n, x, y, z, ev_c, e, dt)
    if chain:
        _chain_steps(ev_foot, ev_k, ev_kind, used, n, n_feet, d, out_p, sm_p, offset, seen)
