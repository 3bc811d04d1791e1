"""Independent references for the Burridge-Knopoff chain: written from the equations with
scipy, sharing no code with the C fault solver or the FMUs.

:func:`scipy_slides` is the chain as a user would write it: ``solve_ivp`` over every
block's position and velocity, one terminal event function per switch that can happen
(a sliding block's velocity reaching zero, a stuck block's force reaching +-F), the
modes changed between calls. It is the reference of the small-n checks and the "plain
scipy" side of the benchmark.
"""
from __future__ import annotations

import math

import numpy as np


def _kinetic(F, sigma, alpha, vw, w):
    return F * (1 - sigma) / max(1 + 2 * alpha * w / ((1 - sigma) * vw), 0.5)


def scipy_slides(F, *, m, kc, kp, V, sigma, alpha, vw, stop_time, x0=None,
                 rtol=1e-11, atol=1e-13, max_slides=None, method="DOP853", backward=True):
    """Every slide of every block up to `stop_time` (or `max_slides` ended): a list of
    (block, t_start, t_end, slip), in the order they end; and the final x.

    Free chain ends; blocks start stuck at `x0` (default 0), with v = 0. `backward`
    False: a block never slides backward (Carlson & Langer), pushed back it stays stuck.
    """
    from scipy.integrate import solve_ivp  # scipy: only for a reference run

    F = np.asarray(F, dtype=float)
    n = F.size
    x = np.zeros(n) if x0 is None else np.array(x0, dtype=float)
    v = np.zeros(n)
    q = np.zeros(n, dtype=int)

    def coupling(xx, i):
        f = 0.0
        if i > 0:
            f += xx[i - 1] - xx[i]
        if i + 1 < n:
            f += xx[i + 1] - xx[i]
        return kc * f

    def applied(t, xx, i):
        return coupling(xx, i) + kp * (V * t - xx[i])

    def rhs(t, y):
        xx, vv = y[:n], y[n:]
        dy = np.zeros(2 * n)
        for i in range(n):
            if q[i] == 0:
                continue
            fr = q[i] * _kinetic(F[i], sigma, alpha, vw, q[i] * vv[i])
            dy[i] = vv[i]
            dy[n + i] = (applied(t, xx, i) - fr) / m
        return dy

    def events_for_modes():
        evs = []
        for i in range(n):
            if q[i] != 0:
                def stop(t, y, i=i):
                    return q[i] * y[n + i]
                stop.terminal, stop.direction = True, -1
                evs.append(stop)
            else:
                def forward(t, y, i=i):
                    return F[i] - applied(t, y[:n], i)

                def back(t, y, i=i):
                    # only forward slides: a constant, which never crosses, keeps the
                    # events two per stuck block
                    return F[i] + applied(t, y[:n], i) if backward else 1.0
                forward.terminal = back.terminal = True
                forward.direction = back.direction = -1
                evs += [forward, back]
        return evs

    slides, seg = [], {}
    t = 0.0
    for i in range(n):  # already past a threshold at the start
        A = applied(0.0, x, i)
        if A >= F[i] or (backward and A <= -F[i]):
            q[i], seg[i] = (1 if A > 0 else -1), (0.0, x[i])
    while t < stop_time and (max_slides is None or len(slides) < max_slides):
        if not q.any():  # all stuck: the earliest break-away in closed form
            times = [(F[i] - applied(0.0, x, i)) / (kp * V) if kp * V > 0 else math.inf
                     for i in range(n)]
            i = int(np.argmin(times))
            if not times[i] < stop_time:
                break
            t = max(t, times[i])
            q[i], seg[i] = 1, (t, x[i])
            continue
        evs = events_for_modes()
        sol = solve_ivp(rhs, (t, stop_time), np.concatenate([x, v]), method=method,
                        rtol=rtol, atol=atol, events=evs)
        y_end = sol.y[:, -1]
        x, v = y_end[:n].copy(), y_end[n:].copy()
        t = float(sol.t[-1])
        if sol.status != 1:
            break
        # which event fired: the one whose time is the stop time
        k = min((j for j, te in enumerate(sol.t_events) if len(te)),
                key=lambda j: sol.t_events[j][0])
        ye = sol.y_events[k][0]
        x, v, t = ye[:n].copy(), ye[n:].copy(), float(sol.t_events[k][0])
        # map event k back to a block and a kind
        j = 0
        for i in range(n):
            width = 1 if q[i] != 0 else 2
            if k < j + width:
                block, which = i, k - j
                break
            j += width
        if q[block] != 0:  # the slide ends: stuck, or on from rest if the force holds on
            v[block] = 0.0
            A = applied(t, x, block)
            if A >= F[block]:
                q[block] = 1
            elif backward and A <= -F[block]:
                q[block] = -1
            else:
                t0, x_start = seg.pop(block)
                slides.append((block, t0, t, x[block] - x_start))
                q[block] = 0
        else:
            q[block] = 1 if which == 0 else -1
            seg[block] = (t, x[block])
    return slides, x


__all__ = ["scipy_slides"]
