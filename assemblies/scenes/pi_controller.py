"""A PI speed controller FMU made by tools other than ours, and its closed loop with a
sliding mass solved by hand: the foreign FMU of the ``speed_control`` scene and of the
foreign-FMU tests.

- :func:`casadi_pi_fmu`: the controller exported by CasADi's own
  ``DaeBuilder.export_fmu`` (FMI 3.0 Model Exchange; CasADi's wrapper, not our runtime),
  compiled and zipped by CasADi's ``compile_fmu``/``pack_fmu``;
- :func:`pythonfmu_pi_fmu`: the same controller written with ``pythonfmu`` (FMI 2.0
  Co-Simulation; a C++ wrapper that runs the Python class in an embedded interpreter;
  ``pythonfmu`` is needed only for this one).

Both are built once per machine into ``$MECHFMU_CACHE/foreign/<tag>-<hash>/`` (the tool's
version and the hash of the generating script), so they are paid for once.

The controller: ``f = k (e + I / Ti)``, ``e = v_ref - v``, ``dI/dt = e`` (I [m], the
integral of the speed error), with input ``v`` [m/s], output ``f`` [N] and parameters
``v_ref`` [m/s], ``k`` [N.s/m], ``Ti`` [s]. :func:`pi_on_sliding_mass` is the closed
loop with a mass sliding forward against kinetic Coulomb friction, solved by hand;
:func:`euler_pi_on_sliding_mass` the same loop co-simulated with inputs held.
"""
from __future__ import annotations

import hashlib
import math
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

PI_DEFAULTS = dict(v_ref=1.0, k=2.0, Ti=0.5)

CASADI_SCRIPT = '''
import casadi as ca
dae = ca.DaeBuilder("PIController")
v = dae.add("v", "input", dict(unit="m/s", description="measured speed", start=0.0))
v_ref = dae.add("v_ref", "parameter", "tunable",
                dict(unit="m/s", description="speed set point", start={v_ref!r}))
k = dae.add("k", "parameter", "tunable", dict(unit="N.s/m", description="gain", start={k!r}))
Ti = dae.add("Ti", "parameter", "tunable",
             dict(unit="s", description="integral time", start={Ti!r}))
I = dae.add("I", dict(unit="m", description="integral of the speed error", start=0.0))
f = dae.add("f", "output", dict(unit="N", description="force on the mass"))
dae.eq(dae.der(I), v_ref - v)
dae.eq(f, k * (v_ref - v + I / Ti))
files = dae.export_fmu(dict(no_warning=True))
files = dae.compile_fmu(files, dict(include_dirs=[{include!r}]))
dae.pack_fmu(files, dict(path="PIController.fmu"))
'''

PYTHONFMU_SCRIPT = '''
from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Real


class PIControllerPy(Fmi2Slave):
    """PI speed controller f = k (e + I / Ti), e = v_ref - v, dI/dt = e (input held)."""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.v, self.I = 0.0, 0.0
        self.v_ref, self.k, self.Ti = {v_ref!r}, {k!r}, {Ti!r}
        self.register_variable(Real("v", causality=Fmi2Causality.input, start=0.0))
        for name in ("v_ref", "k", "Ti"):
            self.register_variable(Real(name, causality=Fmi2Causality.parameter,
                                        variability=Fmi2Variability.tunable))
        self.register_variable(Real("I", causality=Fmi2Causality.local))
        # read when asked, so f answers the input just set (direct feedthrough)
        self.register_variable(Real("f", causality=Fmi2Causality.output,
                                    getter=lambda: self.k * (self.v_ref - self.v
                                                             + self.I / self.Ti)))

    def do_step(self, current_time, step_size):
        self.I += (self.v_ref - self.v) * step_size  # exact for the input held over the step
        return True
'''


def _cache(tag: str, text: str) -> Path:
    from fmus.build import cache_dir
    return cache_dir() / "foreign" / f"{tag}-{hashlib.sha256(text.encode()).hexdigest()[:16]}"


def _built(tag: str, text: str, name: str, make) -> Path:
    """`name` in the cache folder of (tag, text), made by `make(workdir)` if missing."""
    folder = _cache(tag, text)
    target = folder / name
    if target.exists():
        return target
    folder.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=folder) as work:
        make(Path(work))
        os.replace(Path(work) / name, target)  # atomic: a half-built FMU is never seen
    return target


def casadi_pi_fmu() -> Path:
    """The PI controller as CasADi exports it (FMI 3.0 Model Exchange)."""
    import casadi
    import fmpy
    include = str(Path(fmpy.__file__).parent / "c-code")  # the FMI 3 headers
    script = CASADI_SCRIPT.format(include=include, **PI_DEFAULTS)

    def make(work: Path):
        # export_fmu writes into the current directory: a child process keeps ours
        subprocess.run([sys.executable, "-c", script], cwd=work, check=True,
                       capture_output=True, text=True)

    return _built(f"casadi{casadi.__version__}", script, "PIController.fmu", make)


def pythonfmu_pi_fmu(handle_state: bool = False) -> Path:
    """The PI controller as pythonfmu builds it (FMI 2.0 Co-Simulation). pythonfmu
    declares canGetAndSetFMUstate false unless asked (`handle_state`)."""
    import pythonfmu
    script = PYTHONFMU_SCRIPT.format(**PI_DEFAULTS)
    flags = ["--handle-state"] if handle_state else []

    def make(work: Path):
        (work / "PIControllerPy.py").write_text(script)
        subprocess.run([sys.executable, "-m", "pythonfmu", "build", "-f", "PIControllerPy.py",
                        "-d", ".", *flags], cwd=work, check=True, capture_output=True, text=True)

    return _built(f"pythonfmu{pythonfmu.__version__}{'-state' * handle_state}", script,
                  "PIControllerPy.fmu", make)


def _error_oscillation(m, friction, v_ref, k, Ti, v0=0.0):
    """(sigma, wd, a, b) of the speed error e = exp(-sigma t) (a cos wd t + b sin wd t)
    of the loop of :func:`pi_on_sliding_mass`."""
    sigma, omega2 = k / (2 * m), k / (m * Ti)
    if sigma**2 >= omega2:
        raise ValueError("pi_on_sliding_mass: this closed form is for the underdamped loop")
    wd = math.sqrt(omega2 - sigma**2)
    e0 = v_ref - v0
    de0 = -(k * e0 - friction) / m                    # e' = -v' at t = 0, I(0) = 0
    return sigma, wd, e0, (de0 + sigma * e0) / wd


def pi_on_sliding_mass(t, m, friction, v_ref, k, Ti, v0=0.0):
    """(v, f) of a mass sliding forward (v > 0 throughout) against a constant kinetic
    friction `friction` [N], pushed by the PI controller's force, from v(0) = v0, I(0) = 0.

    m v' = f - friction, f = k (e + I/Ti), I' = e, e = v_ref - v. Differentiating,
    m e'' + k e' + (k/Ti) e = 0: a damped oscillator in e (the friction only sets
    where I settles, I = Ti friction / k). Closed form for the underdamped case
    (k² < 4 m k / Ti), which the tests and the scene use.
    """
    t = np.asarray(t, dtype=float)
    sigma, wd, a, b = _error_oscillation(m, friction, v_ref, k, Ti, v0)
    decay = np.exp(-sigma * t)
    e = decay * (a * np.cos(wd * t) + b * np.sin(wd * t))
    de = decay * ((b * wd - sigma * a) * np.cos(wd * t) - (a * wd + sigma * b) * np.sin(wd * t))
    # f from the mass's equation: f = friction + m v' = friction - m e'
    return v_ref - e, friction - m * de


def pi_first_turning_point(m, friction, v_ref, k, Ti, v0=0.0) -> tuple[float, float]:
    """(t, v) at the first t > 0 where the speed of :func:`pi_on_sliding_mass` turns
    (e' = 0): from rest below the set point, the overshoot's peak.

    e' = exp(-sigma t) (c cos wd t - d sin wd t), c = b wd - sigma a, d = a wd + sigma b,
    vanishes where wd t = atan2(c, d) modulo pi."""
    sigma, wd, a, b = _error_oscillation(m, friction, v_ref, k, Ti, v0)
    phase = math.atan2(b * wd - sigma * a, a * wd + sigma * b) % math.pi
    t = (phase or math.pi) / wd
    return t, float(pi_on_sliding_mass(t, m, friction, v_ref, k, Ti, v0)[0])


def pi_error_envelope(t, m, friction, v_ref, k, Ti, v0=0.0) -> float:
    """A bound on |e(t)| of :func:`pi_on_sliding_mass`: exp(-sigma t) sqrt(a² + b²); |e'|
    and each further derivative are at most sqrt(k / (m Ti)) times the previous bound."""
    sigma, _, a, b = _error_oscillation(m, friction, v_ref, k, Ti, v0)
    return math.exp(-sigma * t) * math.hypot(a, b)


def euler_pi_on_sliding_mass(n_steps, h, m, friction, v_ref, k, Ti, v0=0.0):
    """(v, f) at t = 0, h, ..., n h of the same loop co-simulated with constant inputs
    held over each communication step (Jacobi): the mass under a held force slides with
    constant acceleration, the controller integrates a held error, so the coupled
    system is exactly forward Euler on (v, I)."""
    v, integral = np.empty(n_steps + 1), 0.0
    f = np.empty(n_steps + 1)
    v[0] = v0
    for n in range(n_steps + 1):
        e = v_ref - v[n]
        f[n] = k * (e + integral / Ti)
        if n < n_steps:
            v[n + 1] = v[n] + h * (f[n] - friction) / m
            integral += h * e
    return v, f


__all__ = ["PI_DEFAULTS", "casadi_pi_fmu", "euler_pi_on_sliding_mass", "pi_error_envelope",
           "pi_first_turning_point", "pi_on_sliding_mass", "pythonfmu_pi_fmu"]
