"""Error estimation and step-size control for the adaptive co-simulation master.

The estimate is step doubling (Richardson): from the FMUs' saved state, one
communication step of h and two of h/2. If the coupling's local error is
C h^(p+1) (global order p), the two results differ by C h^(p+1) (1 - 2^-p), so
the error of the two-half-step result, the one kept, is that difference over
(2^p - 1). It is measured on the FMUs' continuous states (absolute, in their
own units: m, m/s, ...), because outputs such as friction forces jump at events
and would say nothing about the error that persists.

The step is accepted when the estimate is at most ``tol * h / horizon`` (error
per unit step): the local errors then add up to at most about ``tol`` over the
horizon, which is what makes the *global* error, the one a user compares with a
reference, follow the requested tolerance. To that allowance is added the noise
of the FMUs' own solvers: the two runs of step doubling cannot agree better than
that, and without the floor the step would shrink without end where the coupling
error is smaller. It is their tolerance, relative to each state, per output
interval: a step of h takes h / h_max of it, never less than NOISE_SHARE_MIN (what
no step length removes: round-off and the FMUs' event location left 1e-13 in
x = 30 m on conveyor, where the step then fell to 3e-13 s). The whole tolerance in
every step, as it was, let the allowed error grow with the number of steps: on
conveyor (|x| up to 40 m, FMU tolerance 1e-8) 4e-7 per step against tol 1e-3's
1.3e-8, so every tol <= 1e-3 took the same steps and ended 6.6e-6 off the
composite; now 5.2e-7, 1.9e-7 and 1.5e-7 at tol 1e-3, 1e-4, 1e-5. The
next step comes from the standard controller
h * min(4, max(0.2, 0.9 (allowed / estimate)^(1/p))) (the exponent is 1/p, not
1/(p+1), because the allowed error itself grows with h). A rejected step shrinks
by what the estimate says, at least by 0.9 (halving regardless wastes steps where
the error is close to the noise floor), and the step after a rejection does not
grow (Hairer's rule against reject/accept cycles).

After each accepted estimate, COAST_STEPS steps of the half step it found good are
taken without one (``coast``): step doubling costs three doSteps to advance two half
steps, so on a scene whose steps stay about even (a table shaken at one frequency)
adaptivity would cost 1.5x fixed steps of the same length; with the run of unjudged
steps, (3 + 4) / (2 + 4) = 1.17x. An event in a step, a start event moved back, or a
chain defect over its allowance (known after every step, at no cost) ends the run;
the defect also rejects the step.

A run grows while the estimates say the error is steady: after a run that ran to its
end, an estimate that keeps the step within COAST_STEADY of the step asked for (or the
output interval caps it) doubles the next run, up to COAST_MAX; any other estimate (a
step that should grow or shrink changes fastest with short runs), an event or a run
cut short sets it back to COAST_STEPS, except a rejection after a full run that
shrinks the step by less than COAST_KEEP. What keeps a long run honest
costs no doStep: every unjudged step compares each coupling's extrapolation with what
its source returned at the step's end (the coupling defect, relative to the value:
held inputs against the polynomial their step mean came from, chains against the
FMU's Taylor chain). Grown past COAST_DEFECT_GROWTH times its value at the estimate's
second half step (of the run's length; at the output interval, which no estimate
can lengthen, the largest since the run last reset), plus ten times the FMUs'
tolerance, it
rejects the step and estimates again: the estimate stays valid while the couplings
move as they did when it was made. On moving_table, whose step error depends on the
table's phase, runs of up to 32 without that check ended 2.6e-2 off at tol 1e-2
and 4.9e-4 at 1e-3; with it 1.7e-3 and 2.4e-5, and runs of 4 did 5.9e-4 and 1.8e-4
(block.s against the monolithic model).

Steps fit the output grid (``cells``): the steps from where one starts to the next
output point are equal, as many as the step asked for needs (together up to a quarter
of one longer, the old allowance for the one step before an output point, now spread
over them all), and an estimate takes two of them. Before, the steps ran at the length
asked for and the last one before each output point was what was left: an estimate
taken on that remnant made the next run's steps half of it and started the run again
at COAST_STEPS (beam_friction_damper at tol 1e-2: runs of 1.6 ms steps in intervals
of 12.5 ms where the estimate allowed 6.25 ms). Now a run's steps come from the step
asked for (the smaller of it and the next, halved), an estimate whose two halves do
not fit before the output point is put off to it (the run goes on by one step, once,
judged by the coupling defect as every step of it), and a run the coupling defect
ended (COAST_GUARDED) is no run cut short: where the estimate that follows keeps the
step, the next run is as long (not doubled). beam_friction_damper at tol 1e-2: doSteps
per step and instance 1.37 -> 1.26, 18,898 -> 15,150 doSteps.

The step asked for may be up to ESTIMATE_SPAN = 2 output intervals, though no step
goes past an output point: an estimate then takes the whole interval in two halves,
and, once the estimates are steady (as for a run's growth), the unjudged steps that
follow, each half the step asked for, run a whole output interval each. Capped at one
interval, a run's steps were half of it however smooth the motion, and
two_block_belt's steady sliding took two steps per output interval (tol 1e-4: 6,530
steps for 3,000 intervals; now 5,172). Before the estimates are steady, the run's
steps stay within the estimate's halves: beam_friction_damper's ringing pad rejected
such longer steps (tol 1e-2, measured before the defect reference took its current
rule, cosim.c: 159 rejections and 11,486 doSteps ungated, against 145 and 10,864
gated). The coupling defect of a run's step longer than the estimate's half
steps it is compared with is scaled up as the extrapolation's error, by
(h / h_ref)^(p + 1) (defect_allowance): unscaled, every such step was taken for a
changed coupling and estimated again.

This is the compiled engine's controller (``judge`` in assemblies/engine/c/cosim.c).
"""
from __future__ import annotations

import math

import numpy as np

COAST_STEPS = 4  # unjudged steps after an accepted estimate (module doc)
COAST_MAX = 32  # the longest run of them, while the error stays steady (module doc)
COAST_STEADY = 0.8  # the next step within this factor of the last: steady (module doc)
COAST_KEEP = 0.5  # a rejection shrinking the step by less keeps the run's length
COAST_DEFECT_GROWTH = 2.0  # coupling defect over this times the estimate's: estimate again
COAST_GUARDED = 2  # the coupling defect ended the run (module doc)
ORDER_MAX = 3  # the highest order step doubling takes a coupling to be of (cosim.c says why)
FIT_STRETCH = 0.25  # the steps of an output interval may grow by a quarter of one in all
ESTIMATE_SPAN = 2.0  # the step asked for may be this many output intervals (module doc)
NOISE_SHARE_MIN = 1e-4  # the least share of the FMUs' tolerance taken as noise (module doc)


def defect_allowance(defect_ref: float, h_ref: float, h: float, order: int,
                     tolerance: float) -> float:
    """How far a run's unjudged step of `h` may take its coupling defect: COAST_DEFECT_GROWTH
    times the estimate's (`defect_ref`, at its half step `h_ref`), grown as the
    extrapolation's error of polynomial order `order` where the step is longer, plus ten
    times the FMUs' tolerance (module doc; cosim.c defect_allowance)."""
    growth = (h / h_ref) ** (order + 1) if h > h_ref else 1.0
    return COAST_DEFECT_GROWTH * defect_ref * growth + 10.0 * tolerance


def cells(left: float, h: float, stretch: bool) -> float:
    """How many equal steps of about `h` fill `left`: each at most `h`, or together a
    quarter of one longer (`stretch`), never fewer than one (cosim.c cells). A ratio that
    is a whole number to round-off stays that number."""
    return max(1.0, float(math.ceil(left / h - (FIT_STRETCH if stretch else 1e-9))))


class StepController:
    def __init__(self, tol: float, order: int, horizon: float, h_max: float):
        if not (math.isfinite(tol) and tol > 0):
            raise ValueError(f"adaptive tolerance must be a positive finite number, not {tol}")
        self.tol, self.order, self.horizon, self.h_max = tol, order, horizon, h_max
        self.h_cap = ESTIMATE_SPAN * h_max  # the longest step asked for (module doc)
        self.accepted = 0
        self.rejected = 0
        self.rejected_last = False  # the last judged step was rejected
        self.max_ratio = 0.0  # largest accepted estimate / allowed, a self-check for reports

    @staticmethod
    def min_step(t: float) -> float:
        """The shortest step at time t: what time resolves there (the solvers' and the C
        engine's MF_MIN_STEP), not a share of the horizon, which refused the short steps
        a friction onset needs late in a long run (1e-12 x 1e4 s)."""
        return 1e-14 * max(1.0, abs(t))

    def estimate(self, coarse: np.ndarray, fine: np.ndarray) -> float:
        """Error of `fine` (two half steps) from its difference to `coarse` (one step)."""
        if coarse.size == 0:
            return 0.0
        return float(np.max(np.abs(fine - coarse))) / (2 ** self.order - 1)

    def noise(self, fine: np.ndarray, tolerance: float, h: float) -> float:
        """What FMU solvers with relative tolerance `tolerance` leave in the states in a
        step of `h`: h / h_max of it (the step's part of an output interval), never less
        than NOISE_SHARE_MIN of it (module doc)."""
        share = max(NOISE_SHARE_MIN, min(1.0, h / self.h_max))
        return float(np.max(tolerance * (1.0 + np.abs(fine)))) * share if fine.size else 0.0

    def allowed(self, h: float) -> float:
        return self.tol * h / self.horizon

    def judge(self, error: float, h: float, noise: float = 0.0, defect: float = 0.0,
              defect_order: int = 1) -> tuple[bool, float]:
        """(accept?, next step) for a step of `h` with estimated error `error`, of
        which `noise` (see :meth:`noise`) no step size can remove; `defect`: how far the
        motion an FMU extrapolated itself strayed from its source's, over its allowance
        (at most 1), shrinking as h^defect_order."""
        allowed = self.allowed(h) + noise
        ok = error <= allowed and defect <= 1.0
        if ok:
            self.accepted += 1
            self.max_ratio = max(self.max_ratio, error / allowed, defect)
        else:
            self.rejected += 1
        factor = 4.0 if error == 0 else min(4.0, max(0.2, 0.9 * (allowed / error) ** (1 / self.order)))
        # the defect is local (each communication point sets the motion afresh): its
        # allowance does not grow with h
        if defect > 0:
            factor = min(factor, max(0.2, 0.9 * defect ** (-1 / defect_order)))
        if not ok:
            factor = min(factor, 0.9)  # a rejected step must shrink
        elif self.rejected_last:
            factor = min(factor, 1.0)  # and the one after it must not grow
        self.rejected_last = not ok
        return ok, min(self.h_cap, h * factor)


__all__ = ["COAST_DEFECT_GROWTH", "COAST_GUARDED", "COAST_KEEP", "COAST_MAX", "COAST_STEADY",
           "COAST_STEPS", "ESTIMATE_SPAN", "FIT_STRETCH", "NOISE_SHARE_MIN", "StepController",
           "cells", "defect_allowance"]
