"""What the plots draw, read back from matplotlib's objects: the seed 9.6 scenes draw the
block's absolute velocity and its cycle mean beside their references (seed Figs. 9.8,
9.10), a conserved quantity's axis reads its drift without an offset, and a parameter
study's axes carry units."""
from __future__ import annotations

import math

import numpy as np
import pytest
from matplotlib.figure import Figure as MplFigure

from assemblies.plot import plot_result
from assemblies.result import Result
from assemblies.run import run_scene_full
from assemblies.scenes.table import CONVEYOR, CONVEYOR_ACCURACY, CONVEYOR_MEASURED_PERIODS

# the seed's numbers for both examples of 9.6: m = g = 1, U = 0.1, omega = 20, mu = 0.4
U, OMEGA, MU = 0.1, 20.0, 0.4
PERIOD = 2 * math.pi / OMEGA


@pytest.fixture
def drawn(monkeypatch):
    """Every matplotlib figure saved while the test runs, drawn (tick texts set)."""
    figures, save = [], MplFigure.savefig

    def keep(fig, *args, **kwargs):
        save(fig, *args, **kwargs)
        figures.append(fig)
    monkeypatch.setattr(MplFigure, "savefig", keep)
    return figures


def _lines(ax):
    return {line.get_label(): line for line in ax.get_lines()}


def _table_velocity(t, coefficients):
    """The table's velocity from its path U sum c_k sin(k omega t) (seed 9.6)."""
    return U * OMEGA * sum(c * k * np.cos(k * OMEGA * t) for k, c in enumerate(coefficients, 1))


def test_moving_table_draws_absolute_velocity_its_cycle_mean_and_the_seed_law(tmp_path, drawn):
    run = run_scene_full("moving_table", mode="me", out=tmp_path)
    (fig,) = drawn
    (ax,) = fig.axes
    lines = _lines(ax)
    t = run.result["time"]
    absolute = lines["absolute velocity of the block"]
    # the block's state is relative to the table: absolute = relative + U omega cos(omega t)
    assert np.allclose(absolute.get_ydata(), run.result["block.v"] + _table_velocity(t, [1]),
                       rtol=0, atol=1e-9)
    assert absolute.get_ydata()[0] == pytest.approx(1.5, abs=1e-12)  # the seed's v(0)
    mean = lines["its mean over each cycle of the table"]
    assert len(mean.get_xdata()) == 64  # one point per cycle of the 64 run, not per event
    assert mean.get_xdata()[0] == pytest.approx(PERIOD / 2)
    # the first cycle's mean against the seed's averaged law before linearising
    v_first = next(f for f in run.figures if f.name == "V_first")
    assert abs(mean.get_ydata()[0] - v_first.reference) <= v_first.bound
    # the dashed line is the seed's V(0) exp(-2 mu g t / (pi omega U)), -0.1273 V
    law = next(line for label, line in lines.items() if label.startswith("seed's averaged law"))
    rate = 2 * MU / (math.pi * OMEGA * U)
    assert rate == pytest.approx(0.1273, abs=5e-5)
    assert np.allclose(law.get_ydata(), 1.5 * np.exp(-rate * law.get_xdata()), rtol=1e-12)
    # no event dots: the block sticks and slips in every cycle
    assert len(lines) == 3 and not any(label.startswith("events") for label in lines)
    assert ax.get_ylabel() == "velocity [m/s]" and ax.get_xlabel() == "time [s]"


def test_conveyor_cycle_means_settle_on_the_exact_periodic_speed(tmp_path, drawn):
    run = run_scene_full("conveyor", mode="me", out=tmp_path)
    (fig,) = drawn
    lines = _lines(fig.axes[0])
    t = run.result["time"]
    absolute = lines["absolute velocity of the block"].get_ydata()
    assert np.allclose(absolute, run.result["block.v"] + _table_velocity(t, CONVEYOR),
                       rtol=0, atol=1e-9)
    assert absolute[0] == pytest.approx(0.0, abs=1e-12)  # the seed starts the block at rest
    steady = next(f for f in run.figures if f.name == "V_steady")
    reference = next(line for label, line in lines.items() if label.startswith("exact"))
    assert np.all(reference.get_ydata() == steady.reference)
    assert steady.reference == pytest.approx(1.069, abs=2e-3)  # the seed's median estimate
    # every cycle of the periodic motion moves the block by the same distance: each of
    # the measured cycles' means is the exact speed, within the scene's accuracy
    means = lines["its mean over each cycle of the table"].get_ydata()
    last = means[-CONVEYOR_MEASURED_PERIODS:]
    assert np.max(np.abs(last - steady.reference)) <= CONVEYOR_ACCURACY
    assert means[0] < 0.1  # and the block starts from rest, far from it


def test_a_conserved_quantity_is_drawn_as_its_drift_without_an_axis_offset(tmp_path, drawn):
    """The beam's energy, 1.520398e-2 J changing by 1e-9 J: matplotlib labelled its axis
    with an offset '1e-9+1.520398e-2'; the panel now shows E - E(0) in J."""
    t = np.linspace(0.0, 40.0, 401)
    energy = 0.01520398236 - 2.5e-11 * t
    result = Result({"time": t, "beam.E": energy, "beam.w_tip": 0.1 * np.cos(t)})
    plot_result(result, ["beam.w_tip", "beam.E"], "beam", tmp_path / "beam.png",
                {"beam.E": "J", "beam.w_tip": "m"})
    (fig,) = drawn
    tip, drift = fig.axes
    assert drift.get_ylabel() == "beam.E - 0.01520398236 [J]"
    assert np.allclose(drift.get_lines()[0].get_ydata(), energy - energy[0], rtol=0, atol=1e-18)
    assert tip.get_ylabel() == "beam.w_tip [m]"  # a varying column is drawn as it is
    assert np.array_equal(tip.get_lines()[0].get_ydata(), 0.1 * np.cos(t))
    for ax in fig.axes:
        # a power of ten may head the axis, never an added offset
        assert "+" not in ax.yaxis.get_offset_text().get_text()


def test_a_study_plot_labels_its_axes_with_units(tmp_path, drawn):
    """block.m is declared in kg, block.x in m; figure t1's description states [s]."""
    pytest.importorskip("pandas")
    from assemblies.sweep import sweep
    table = sweep("stick_slip", {"block.m": [1.0, 2.0]}, outputs=["block.x@end"], workers=0,
                  progress=False, out=tmp_path, plot=["block.x@end", "t1"])
    assert table.attrs["units"]["block.m"] == "kg"
    (fig,) = drawn
    x_panel, t1_panel = fig.axes
    assert x_panel.get_ylabel() == "block.x@end [m]"
    assert t1_panel.get_ylabel() == "t1 [s]"
    assert t1_panel.get_xlabel() == "block.m [kg]"
    # the points are the study's: t1 = mu_s m g / (k v) (seed 9.2)
    assert np.allclose(t1_panel.get_lines()[0].get_ydata(), [8.0, 16.0], atol=1e-6)
