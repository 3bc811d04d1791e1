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


def test_a_foreign_fmus_columns_get_the_units_its_model_description_declares():
    """Our SpringBlock exported and added back as a foreign FMU: the units come from its
    modelDescription.xml and agree with the component's; a handmade FMU that declares
    none gets those its units= gives, and nothing else."""
    from assemblies import Assembly
    from assemblies.foreign import FMU
    from components.translational.spring_block import SpringBlock
    from fmus import build_fmu
    from handmade_fmus import handmade_fmu

    columns = ["block.x", "block.v", "block.f_friction", "block.m"]
    asm = Assembly("foreign")
    asm.add("block", FMU(build_fmu(SpringBlock(name="block", profile="driven"))))
    asm.add("stair", FMU(handmade_fmu("stair2"), units={"y": "s"}))
    asm.add("bare", FMU(handmade_fmu("stair2")))
    own = scene("stick_slip").build()
    assert column_units(asm, columns) == column_units(own, columns) == {
        "block.x": "m", "block.v": "m/s", "block.f_friction": "N", "block.m": "kg"}
    assert column_units(asm, ["stair.y", "stair.counter", "bare.y"]) == {"stair.y": "s"}
