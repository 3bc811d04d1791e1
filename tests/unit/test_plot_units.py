"""Plot panels carry the unit each recorded quantity is declared with."""
from assemblies.plot import column_units
from assemblies.scenes import scene


def test_columns_get_the_units_their_components_declare():
    asm = scene("stick_slip").build()
    # SpringBlock's state x [m], v [m/s] and output f_friction [N]; a name nobody declares
    # gets no unit rather than a guess
    assert column_units(asm, ["block.x", "block.v", "block.f_friction", "block.nothing",
                              "nobody.x"]) == {"block.x": "m", "block.v": "m/s",
                                               "block.f_friction": "N"}
