"""Every FMI variable type through the engine (issue 24, item 1), on two hand-written FMI 3
FMUs (tests/handmade/types_*):

- ``types_scalars`` (Co-Simulation) has a parameter, an output and an input of Int8,
  Boolean, String, Float32, UInt64, Enumeration, Int16/Int32, UInt8/Float64, each got and
  set only through its own FMI call (the FMU answers any other call with fmi3Error), and
  outputs that echo its inputs (UInt16 into UInt32 and Int64 too). Its outputs are written from the time in closed form
  (n = floor(t): n8 = k n, on = flag XOR (n odd), tag = label "-" n, y32 = gain t, big =
  base + n, m = mode, i16 = offset16 + n, u8 = 20 n, u16 = 1000 n, i64 = n - 2^53):
  the references.
- ``types_array`` (Model Exchange and Co-Simulation) is der(x) = -lam .* x + u with x, u,
  lam, y = x of 3 elements and m[2,2] = [[x1, x2], [x3, t]]: an array state, parameter,
  input and outputs. References: exp(-lam t) alone; (1 + t) exp(-lam t) for b.x fed by
  a.y (x0 = 1 both); fmpy's own simulate_fmu on the same FMU.

Before this work, an array FMU did not run at all (the default record asked for one value
of a 3-element output; the array state counted as one) and none of the types but
Float64/Int32 could be recorded, coupled or set.
"""
import math
import zipfile

import numpy as np
import pytest
from fmpy import simulate_fmu

from assemblies import FMU, Assembly, AssemblyError, cosimulate, simulate_me
from assemblies.engine.binding import EngineError
from assemblies.engine.prepare import prepared
from assemblies.foreign import FmuError
from components import ComponentError

from handmade_fmus import handmade_fmu

LAM = np.array([1.0, 2.0, 3.0])
# (output of src, input of dst it feeds, echo output of dst)
LINKS = [("n8", "n8_in", "n8_echo"), ("on", "on_in", "on_echo"), ("tag", "tag_in", "tag_echo"),
         ("y32", "y32_in", "y32_echo"), ("big", "big_in", "big_echo"), ("m", "m_in", "m_echo"),
         ("i16", "i32_in", "i32_echo"),  # Int16 into a wider Int32
         ("u8", "x_in", "x_echo"),        # UInt8 into a Float64: its value
         ("u16", "u32_in", "u32_echo"),   # UInt16 into a wider UInt32
         ("i64", "i64_in", "i64_echo")]   # Int64 at -2^53 + n: exact


NUMERIC = ("n8", "on", "y32", "big", "m", "i16", "u8", "u16", "i64")  # fmpy records no Strings


def one_line(err) -> str:
    text = str(err.value)
    assert "\n" not in text, text
    return text


def scalars_closed_form(t, k=3, flag=False, label="tick", gain=0.5, base=2 ** 52, mode=2,
                        offset16=-300) -> dict:
    n = np.floor(t + 1e-9).astype(int)
    return {"n8": k * n, "on": np.logical_xor(flag, n % 2 == 1).astype(float),
            "tag": [f"{label}-{i}" for i in n], "y32": np.float32(gain) * t.astype(np.float32),
            "big": np.array([base + int(i) for i in n], dtype=object), "m": np.full(len(t), mode),
            "i16": offset16 + n, "u8": 20 * n, "u16": 1000 * n, "i64": n - 2 ** 53}


def round_trip(**src_values) -> Assembly:
    fmu = handmade_fmu("types_scalars")
    asm = Assembly("types")
    asm.add("src", FMU(fmu, **src_values))
    asm.add("dst", FMU(fmu))
    for out, into, _ in LINKS:
        asm.connect(f"src.{out}", f"dst.{into}")
    return asm


def test_every_scalar_type_is_set_coupled_and_recorded_in_its_own_type():
    """Int8, Boolean, String, Float32, UInt64, Enumeration parameters set on src, its
    outputs coupled into dst's inputs of the same (or a wider) type and recorded: every
    column equals the closed form exactly (Float32 to its own precision; the UInt64
    2^53 - 10 + n exactly, as a double carries it), the String columns hold text."""
    values = dict(k=5, flag=True, label="go", gain=0.25, base=2 ** 53 - 10, mode=3,
                  offset16=-7)
    res = cosimulate(round_trip(**values), 4.0, 0.25)
    t = res["time"]
    ref = scalars_closed_form(t, **values)
    for out, _, echo in LINKS:
        for column in (f"src.{out}", f"dst.{echo}"):
            got = res[column]
            if out == "tag":
                assert got.dtype == object and list(got) == ref["tag"], column
            elif out == "big":
                assert [int(v) for v in got] == list(ref["big"]), column
            else:
                np.testing.assert_array_equal(got, np.asarray(ref[out], dtype=float), column)
    # dst kept its own defaults: label "tick", k = 3
    assert list(res["dst.tag"]) == scalars_closed_form(t)["tag"]
    np.testing.assert_array_equal(res["dst.n8"], 3 * np.floor(t + 1e-9))


def test_every_scalar_type_round_trips_in_model_exchange_too():
    """The same round trip in mode 'me' (the FMU's Model Exchange interface: n is a discrete
    state moved at the time event it announces for each whole second). Away from the event
    instants every column equals the closed form; at them too, the echo equals its source
    (the Strings included: String parameters reach the FMU in 'me' as well)."""
    values = dict(k=-5, flag=True, label="me", gain=4.0, base=2 ** 53 - 10, mode=1,
                  offset16=100)
    res = simulate_me(round_trip(**values), 4.0, 0.25)
    t = res["time"]
    ref = scalars_closed_form(t, **values)
    away = np.abs(t - np.round(t)) > 1e-6
    for out, _, echo in LINKS:
        src, dst = res[f"src.{out}"], res[f"dst.{echo}"]
        assert list(src) == list(dst), out
        if out == "tag":
            assert [v for v, a in zip(src, away) if a] == [v for v, a in zip(ref["tag"], away) if a]
        elif out == "big":
            assert [int(v) for v in src[away]] == list(ref["big"][away])
        else:
            np.testing.assert_array_equal(src[away], np.asarray(ref[out], dtype=float)[away], out)


def test_scalar_outputs_match_fmpys_own_run_of_the_fmu():
    """The same FMU, the same parameters, through fmpy.simulate_fmu: every numeric output
    equal at every output point (fmpy records no Strings)."""
    values = dict(k=-4, flag=True, gain=2.0, base=123, mode=1, offset16=11)
    asm = Assembly("one")
    asm.add("src", FMU(handmade_fmu("types_scalars"), **values))
    ours = cosimulate(asm, 3.0, 0.5)
    theirs = simulate_fmu(str(handmade_fmu("types_scalars")), stop_time=3.0, output_interval=0.5,
                          start_values=values, output=list(NUMERIC))
    np.testing.assert_array_equal(ours["time"], theirs["time"])
    for name in NUMERIC:
        np.testing.assert_array_equal(ours[f"src.{name}"], theirs[name].astype(float), name)


def test_values_are_checked_against_their_type_in_one_line():
    fmu = handmade_fmu("types_scalars")
    for key, value, why in [("k", 200, r"k is an Int8 variable: it takes whole numbers from "
                                       r"-128 to 127"),
                            ("k", 1.5, "k is an Int8 variable: it takes whole numbers"),
                            ("flag", 2, r"flag is a Boolean variable: it takes True/False"),
                            ("label", 3, r"label is a String variable: it takes text"),
                            ("base", 2 ** 53 + 1, r"base is a UInt64 variable: it takes whole "
                                                  r"numbers from 0 to 9007199254740992 \(the "
                                                  r"engine carries values as doubles"),
                            ("base", -1, "base is a UInt64 variable"),
                            ("gain", "fast", "gain is a Float32 variable: it takes a number")]:
        with pytest.raises(ComponentError, match=why) as err:
            FMU(fmu, **{key: value})
        assert one_line(err).startswith("FMU 'types_scalars' (")


def test_an_int64_output_beyond_2_53_fails_the_run_naming_it():
    """big = base + n passes 2^53 at t = 2 s: the run stops there with one line naming the
    instance and the exact value (2^53 + 1, which a double would have rounded to 2^53)."""
    asm = Assembly("big")
    asm.add("src", FMU(handmade_fmu("types_scalars"), base=2 ** 53 - 1))
    with pytest.raises(EngineError) as err:
        cosimulate(asm, 4.0, 0.5, record=["src.big"])
    text = one_line(err)
    assert text.startswith("src: get of a recorded output failed at t = 2: src: UInt64 "
                           "variable (value reference 14) has the value 9007199254740993, "
                           "beyond 2^53")


def test_connections_follow_the_type_rule_in_one_line():
    """A float never feeds an integer nor a Boolean, a Boolean or String only its own type,
    an integer only a wider one; an integer feeds a float (as above: u8 -> x_in)."""
    fmu = handmade_fmu("types_scalars")
    asm = Assembly("rules")
    asm.add("a", FMU(fmu))
    asm.add("b", FMU(fmu))
    for src, dst, types in [("a.y32", "b.n8_in", "a Float32 output cannot feed an Int8 input"),
                            ("a.x_echo", "b.on_in", "a Float64 output cannot feed a Boolean"),
                            ("a.on", "b.i32_in", "a Boolean output cannot feed an Int32"),
                            ("a.tag", "b.x_in", "a String output cannot feed a Float64"),
                            ("a.i16", "b.n8_in", "an Int16 output cannot feed an Int8"),
                            ("a.m", "b.i32_in", "an Enumeration output cannot feed")]:
        with pytest.raises(AssemblyError) as err:
            asm.connect(src, dst)
        assert one_line(err).startswith(f"cannot connect {src} to {dst}: {types}")
    asm.connect("a.y32", "b.x_in")  # Float32 into Float64
    asm.connect("b.n8", "a.i32_in")  # Int8 into Int32


def _rewritten(tmp_path, old: str, new: str):
    """types_scalars with one line of its model description replaced."""
    source = handmade_fmu("types_scalars")
    target = tmp_path / "types_scalars.fmu"
    with zipfile.ZipFile(source) as zin, zipfile.ZipFile(target, "w") as zout:
        for item in zin.infolist():
            data = zin.read(item)
            if item.filename == "modelDescription.xml":
                text = data.decode()
                assert old in text
                data = text.replace(old, new).encode()
            zout.writestr(item, data)
    return target


def test_binary_and_clock_variables_the_user_reaches_refuse_the_fmu(tmp_path):
    """A local Binary (types_scalars' blob) does not matter; a Binary parameter or a Clock
    input refuses the FMU when it is added, in one line naming the variable."""
    FMU(handmade_fmu("types_scalars"))  # its local Binary is left alone
    blob = '<Binary name="blob" valueReference="40" causality="local" variability="discrete" ' \
           'initial="exact">'
    binary = _rewritten(tmp_path, blob, blob.replace('causality="local" variability="discrete" '
                                                     'initial="exact"',
                                                     'causality="parameter" variability="fixed"'))
    with pytest.raises(FmuError) as err:
        FMU(binary)
    assert one_line(err) == ("FMU 'types_scalars.fmu': parameter variable 'blob' is of type "
                             "Binary, which the engine cannot carry (Binary and Clock variables "
                             "are not supported)")
    (tmp_path / "c").mkdir()
    clock = _rewritten(tmp_path / "c", blob, '<Clock name="tick" valueReference="41" '
                       'causality="input" variability="discrete" intervalVariability="triggered"/>'
                       + blob)
    with pytest.raises(FmuError, match=r"input variable 'tick' is of type Clock") as err:
        FMU(clock)
    one_line(err)


# --- arrays ---------------------------------------------------------------------------------
def array_fmu(**values) -> FMU:
    return FMU(handmade_fmu("types_array"), **values)


def test_an_array_fmu_runs_alone_in_both_interfaces():
    """Columns per element, row-major (m[1,2] is x2, m[2,2] is the time), within the
    solver's tolerance of exp(-lam t) in 'me' and exactly (the FMU's own exact step, 1e-15)
    in 'cosim'; the array state counts as 3 states."""
    fmu = prepared(array_fmu())
    assert fmu.n_states == 3 and fmu.states == ["x[1]", "x[2]", "x[3]"]
    assert fmu.outputs == ["y[1]", "y[2]", "y[3]", "m[1,1]", "m[1,2]", "m[2,1]", "m[2,2]"]
    for run, tol in ((simulate_me, 1e-8), (cosimulate, 1e-14)):
        asm = Assembly("alone")
        asm.add("a", array_fmu())
        res = run(asm, 2.0, 0.25, tolerance=1e-11)
        t = res["time"]
        assert res.columns == ["time", "a.y[1]", "a.y[2]", "a.y[3]", "a.m[1,1]", "a.m[1,2]",
                               "a.m[2,1]", "a.m[2,2]"]
        for i in range(3):
            exact = np.exp(-LAM[i] * t)
            assert np.abs(res[f"a.y[{i + 1}]"] - exact).max() < tol
        np.testing.assert_array_equal(res["a.m[1,2]"], res["a.y[2]"])
        np.testing.assert_array_equal(res["a.m[2,1]"], res["a.y[3]"])
        np.testing.assert_array_equal(res["a.m[2,2]"], t)


def test_array_parameters_and_state_starts_are_set_per_element_and_match_fmpy():
    """lam[2] = 0.5 and x[3] starting at 2: our Model Exchange run against fmpy's
    simulate_fmu of the same FMU with the same start values, and both against the closed
    form."""
    lam, x0 = np.array([1.0, 0.5, 3.0]), np.array([1.0, 1.0, 2.0])
    asm = Assembly("set")
    asm.add("a", array_fmu(**{"lam[2]": 0.5, "x[3]": 2.0}))
    ours = simulate_me(asm, 2.0, 0.25, tolerance=1e-11, record=["a.y"])
    theirs = simulate_fmu(str(handmade_fmu("types_array")), fmi_type="ModelExchange",
                          stop_time=2.0, output_interval=0.25, relative_tolerance=1e-11,
                          start_values={"lam": lam, "x": x0}, output=["y"])
    t = ours["time"]
    np.testing.assert_allclose(theirs["time"], t, atol=1e-12)
    for i in range(3):
        exact = x0[i] * np.exp(-lam[i] * t)
        assert np.abs(ours[f"a.y[{i + 1}]"] - exact).max() < 1e-8
        assert np.abs(ours[f"a.y[{i + 1}]"] - theirs["y"][:, i]).max() < 1e-6


def test_arrays_couple_whole_by_their_names():
    """b.u <- a.y: b.x = (1 + t) exp(-lam t) in 'me' (within 1e-8); in 'cosim' each step
    holds a.y at its start, so b.x follows b <- b d + a (1 - d) / lam, d = exp(-lam h),
    which it does exactly."""
    def pair():
        asm = Assembly("pair")
        asm.add("a", array_fmu())
        asm.add("b", array_fmu())
        asm.connect("a.y", "b.u")
        return asm

    me = simulate_me(pair(), 2.0, 0.25, tolerance=1e-11, record=["b.y"])
    t = me["time"]
    for i in range(3):
        assert np.abs(me[f"b.y[{i + 1}]"] - (1 + t) * np.exp(-LAM[i] * t)).max() < 1e-8
    h = 0.25
    cs = cosimulate(pair(), 2.0, h, record=["a.y", "b.y"])
    for i in range(3):
        d = math.exp(-LAM[i] * h)
        a, b = cs[f"a.y[{i + 1}]"], cs[f"b.y[{i + 1}]"]
        expected = b[:-1] * d + a[:-1] * (1 - d) / LAM[i]
        np.testing.assert_allclose(b[1:], expected, rtol=1e-14, atol=1e-15)


def test_an_array_connects_to_an_array_of_its_shape_only():
    asm = Assembly("shapes")
    asm.add("a", array_fmu())
    asm.add("s", FMU(handmade_fmu("types_scalars")))
    with pytest.raises(AssemblyError) as err:
        asm.connect("a.y", "s.x_in")
    assert one_line(err) == ("cannot connect a.y to s.x_in: a.y is an array [3], s.x_in is a "
                             "scalar; arrays connect whole, to an array of one shape")
    with pytest.raises(AssemblyError, match=r"a.m is an array \[2, 2\], a.u is an array \[3\]"):
        asm.connect("a.m", "a.u")


def test_fmi2_integer_boolean_enumeration_and_string_round_trip():
    """FMI 2 (types_fmi2): Integer, Boolean, Enumeration (through fmi2Get/SetInteger) and
    String parameters set, outputs coupled into another instance and recorded: equal to the
    closed form (count = step n, on = flag XOR (n odd), tag = label "-" n, m = mode) and,
    for the numbers, to fmpy's simulate_fmu of the same FMU."""
    fmu = handmade_fmu("types_fmi2")
    values = dict(step=-2, flag=True, mode=3, label="two")
    asm = Assembly("fmi2")
    asm.add("src", FMU(fmu, **values))
    asm.add("dst", FMU(fmu))
    for out, into in (("count", "n_in"), ("on", "on_in"), ("tag", "tag_in"), ("m", "m_in")):
        asm.connect(f"src.{out}", f"dst.{into}")
    res = cosimulate(asm, 3.0, 0.5)
    n = np.floor(res["time"] + 1e-9).astype(int)
    expected = {"count": -2.0 * n, "on": (n % 2 == 0).astype(float), "m": np.full(len(n), 3.0)}
    for out, echo in (("count", "n_echo"), ("on", "on_echo"), ("m", "m_echo")):
        np.testing.assert_array_equal(res[f"src.{out}"], expected[out], out)
        np.testing.assert_array_equal(res[f"dst.{echo}"], expected[out], echo)
    assert list(res["src.tag"]) == list(res["dst.tag_echo"]) == [f"two-{i}" for i in n]
    theirs = simulate_fmu(str(fmu), stop_time=3.0, output_interval=0.5,
                          start_values={k: v for k, v in values.items() if k != "label"},
                          output=["count", "on", "m"])
    for out in ("count", "on", "m"):
        np.testing.assert_array_equal(res[f"src.{out}"], theirs[out].astype(float), out)


def test_the_fmpy_reference_master_carries_every_scalar_type_and_refuses_arrays():
    """engine 'fmpy' (assemblies.masters.cosim) gets and sets each type through fmpy's own
    call of that type: the same columns as the engine, value for value; an array FMU is
    refused in one line naming the element (the engine runs it)."""
    from assemblies.masters.cosim import cosimulate as fmpy_cosimulate
    values = dict(k=5, flag=True, label="go", gain=0.25, base=2 ** 53 - 10, mode=3)
    ours = cosimulate(round_trip(**values), 3.0, 0.5)
    theirs = fmpy_cosimulate(round_trip(**values), 3.0, 0.5)
    assert theirs.columns == ours.columns
    for column in ours.columns:
        assert list(theirs[column]) == list(ours[column]), column
    asm = Assembly("arrays")
    asm.add("a", array_fmu())
    with pytest.raises(AssemblyError) as err:
        fmpy_cosimulate(asm, 1.0, 0.5)
    assert one_line(err) == ("a: the fmpy reference master does not get or set FMI 3 arrays "
                             "(lam[1]); run it in the compiled engine (engine 'c')")


def test_the_assembly_fmu_refuses_what_it_cannot_pass_on_in_one_line(tmp_path):
    """export_fmu carries Float64/Int32 scalars only: another type or an array element of a
    member is named in one line (not a KeyError, not a broken FMU)."""
    import warnings

    from assemblies.fmu_export import export_fmu
    for name, why in (("types_scalars", "export_fmu: s.n8_in is of type Int8; the assembly FMU "
                                        "passes on Float64/Real and Int32/Integer only"),
                      ("types_array", "export_fmu: s.u[1] is an element of an FMI 3 array; "
                                      "the assembly FMU passes on scalars only")):
        asm = Assembly("ex")
        asm.add("s", FMU(handmade_fmu(name)))
        with warnings.catch_warnings(), pytest.raises(AssemblyError) as err:
            warnings.simplefilter("ignore")
            export_fmu(asm, tmp_path / f"{name}.fmu", stop_time=1.0, step=0.1)
        assert one_line(err) == why


def test_a_string_parameter_is_set_through_the_assembly():
    asm = Assembly("strings")
    asm.add("s", FMU(handmade_fmu("types_scalars")))
    asm.set("s.label", "fast")
    res = cosimulate(asm, 1.0, 0.5, record=["s.tag"])
    assert list(res["s.tag"]) == ["fast-0", "fast-0", "fast-1"]
    with pytest.raises(ComponentError) as err:
        asm.set("s.label", 1.0)
    assert one_line(err).endswith("label = 1.0 is not allowed; label is a String variable: it "
                                  "takes text (a str)")


def test_a_repeated_model_exchange_run_takes_its_own_values():
    """mode 'me' reuses one plan per structure and refills the values per run: a second
    run with other String, Int8 and UInt64 values shows those, not the first run's."""
    asm = Assembly("again")
    asm.add("s", FMU(handmade_fmu("types_scalars"), label="first", k=2))
    first = simulate_me(asm, 1.5, 0.5, record=["s.tag", "s.n8", "s.big"])
    asm.set("s.label", "second")
    asm.set("s.k", -3)
    asm.set("s.base", 17)
    second = simulate_me(asm, 1.5, 0.5, record=["s.tag", "s.n8", "s.big"])
    assert list(first["s.tag"]) == ["first-0", "first-0", "first-0", "first-1"]
    assert list(second["s.tag"]) == ["second-0", "second-0", "second-0", "second-1"]
    assert list(second["s.n8"]) == [0, 0, 0, -3] and list(second["s.big"]) == [17, 17, 17, 18]
