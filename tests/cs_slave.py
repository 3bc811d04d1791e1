"""A Co-Simulation instance of one of our FMUs through fmpy's low-level classes, for the
tests that call doStep themselves (the FMI 2 and 3 classes differ in name only)."""
from __future__ import annotations

from ctypes import byref

from fmpy import calloc, extract, free, read_model_description
from fmpy.fmi2 import (FMU2Slave, fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                       fmi2CallbackFunctions, fmi2CallbackLoggerTYPE)
from fmpy.fmi3 import FMU3Slave
from fmpy.logging import addLoggerProxy

from fmus import build_fmu


_KEEP = []  # every callbacks struct handed to an FMU, alive as long as the process


def fmi2_callbacks(record):
    """fmi2CallbackFunctions whose logger calls record(status, message bytes); fmpy's
    native proxy does the printf formatting that ctypes cannot.

    The proxy forwards to the Python logger registered last, process-wide, and importing
    the fmpy master (assemblies.masters.cosim) registers its own: callbacks made once
    would lose every message to it whenever a test module imports that master later. So
    each instantiation makes and registers its own, and its messages go where it says."""
    def log(env, name, status, category, message):
        record(status, message)
    cb = fmi2CallbackFunctions()
    cb.logger = fmi2CallbackLoggerTYPE(log)
    cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
    cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
    addLoggerProxy(byref(cb))
    _KEEP.append(cb)
    return cb


def open_slave(component, version: int, log=None, instance_name: str = "block"):
    """(fmu, {variable: value reference}), instantiated. Its messages go to `log` (bytes);
    with none, an FMI 2 instance keeps fmpy's default logger."""
    path = str(build_fmu(component, fmi_version=version))
    md = read_model_description(path)
    cls = FMU2Slave if version == 2 else FMU3Slave
    fmu = cls(guid=md.guid, unzipDirectory=extract(path),
              modelIdentifier=md.coSimulation.modelIdentifier, instanceName=instance_name)
    if version == 2:
        fmu.instantiate(**({} if log is None else
                           {"callbacks": fmi2_callbacks(lambda status, message: log(message))}))
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
