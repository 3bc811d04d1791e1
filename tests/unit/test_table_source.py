"""TimeTable: its two codings agree, its table is checked, its FMU refuses a bad table."""
import casadi as ca
import numpy as np
import pytest

from components import ComponentError, TimeTable, flatten
from components.sources.table import MAX_ROWS, capacity

ROWS = [(0.5, 0.2), (1.0, 1.0), (1.0, 3.0), (2.0, 3.0), (2.5, -1.0), (3.0, 0.5)]


@pytest.mark.parametrize("interpolation", ["linear", "hold"])
def test_loops_in_c_are_the_flattened_equations(interpolation):
    """The MX functions the C code is generated from (loops over the rows) against the
    flattened SX equations, in every segment the mode can hold, at times before, between,
    on and after the rows: equal to the last bit."""
    tt = TimeTable(table=ROWS, interpolation=interpolation, offset=0.3, startTime=0.1)
    model = flatten(tt)
    sx, mx = model.functions(), tt.vectorised_functions(model)
    x, _, u, _ = model.start_vectors()
    p = np.array([tt.values[v.name] for v in model.parameters])
    for t in np.r_[np.linspace(-1.0, 4.0, 401), [r[0] + 0.1 for r in ROWS]]:
        for q in range(tt.option("rows") + 1):
            args = (t, x, q, u, p)
            assert float(mx["out"](*args)[0]) == float(sx["out"](*args))
            assert float(mx["zc"](*args)) == float(sx["zc"](*args))
            assert float(mx["jump"](*args)[1]) == float(sx["jump"](*args)[1])
    assert float(mx["check"](0, x, 0, u, p)) == float(sx["check"](0, x, 0, u, p)) == 0.0


def test_a_table_is_padded_to_a_power_of_two_with_its_last_row():
    tt = TimeTable(table=ROWS)
    assert tt.option("rows") == capacity(len(ROWS)) == 8
    assert tt.table().tolist() == [list(r) for r in ROWS] + [[3.0, 0.5]] * 2


@pytest.mark.parametrize("table, words", [
    ([(0.0, 1.0), (-1.0, 2.0)], r"table times must not decrease; row 2 \(t = -1\) comes "
                                r"before row 1 \(t = 0\)"),
    ([(0.0, 1.0), (1.0, float("nan"))], r"table row 2 is not finite"),
    ([1.0, 2.0], rf"table must be 1 to {MAX_ROWS} rows \[t, y\], not an array of shape \(2,\)"),
    ([("a", 1.0)], r"table must be rows \[t, y\] of numbers"),
    (np.zeros((MAX_ROWS + 1, 2)), rf"table must be 1 to {MAX_ROWS} rows"),
])
def test_a_bad_table_is_one_line(table, words):
    with pytest.raises(ComponentError, match=words):
        TimeTable(name="drive", table=table)


def test_its_fmu_refuses_a_table_set_out_of_order(tmp_path):
    """A table set through the FMU's parameters never passed validate(): the FMU checks
    the order itself when initialisation ends."""
    import fmpy

    from fmus.build import build_fmu
    path = build_fmu(TimeTable(table=[(0.0, 0.0), (1.0, 1.0)]), tmp_path / "tt.fmu")
    with pytest.raises(Exception, match="ExitInitializationMode"):
        fmpy.simulate_fmu(str(path), stop_time=1.0, start_values={"table[2,1]": -1.0})
    res = fmpy.simulate_fmu(str(path), stop_time=2.0, output_interval=0.25, output=["y"])
    assert np.abs(res["y"] - np.clip(res["time"], 0.0, 1.0)).max() < 1e-12
