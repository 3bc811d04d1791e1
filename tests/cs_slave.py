"""A Co-Simulation instance of one of our FMUs through fmpy's low-level classes, for the
tests that call doStep themselves (the FMI 2 and 3 classes differ in name only)."""
from __future__ import annotations

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave

from fmus import build_fmu


def open_slave(component, version: int, log=None, instance_name: str = "block"):
    """(fmu, {variable: value reference}), instantiated. FMI 3 messages go to `log`
    (bytes). FMI 2's logger is variadic, and fmpy's formatting proxy forwards to one
    logger per process (registering ours would take it from other test modules), so an
    FMI 2 instance keeps fmpy's default logger: messages are checked through FMI 3."""
    path = str(build_fmu(component, fmi_version=version))
    md = read_model_description(path)
    cls = FMU2Slave if version == 2 else FMU3Slave
    fmu = cls(guid=md.guid, unzipDirectory=extract(path),
              modelIdentifier=md.coSimulation.modelIdentifier, instanceName=instance_name)
    if version == 2:
        fmu.instantiate()
    else:
        fmu.instantiate(loggingOn=True,
                        logMessage=lambda env, status, category, message: log and log(message))
    return fmu, {v.name: v.valueReference for v in md.modelVariables}


def initialize(fmu, version: int, tolerance: float) -> None:
    """Initialization Mode at t = 0 with `tolerance`, and out of it."""
    if version == 2:
        fmu.setupExperiment(tolerance=tolerance, startTime=0.0)
        fmu.enterInitializationMode()
    else:
        fmu.enterInitializationMode(tolerance=tolerance, startTime=0.0)
    fmu.exitInitializationMode()
