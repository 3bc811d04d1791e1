"""From components to real FMUs: C code generation, modelDescription.xml, gcc, zip."""
from .build import BuildError, build_fmu, cache_dir

__all__ = ["BuildError", "build_fmu", "cache_dir"]
