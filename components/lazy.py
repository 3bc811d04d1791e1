"""A module that is imported when first used, not when its importer is.

CasADi takes 0.1-0.3 s to load and the components use it only to write their equations
(``equations()``, flattening, code generation): a run of FMUs already in the cache,
``mechfmu show`` and ``mechfmu components`` never need it. ``ca = lazy("casadi")`` at the
top of a module keeps ``ca.SX``, ``ca.if_else`` ... as they read, and loads CasADi on the
first such attribute.
"""
from __future__ import annotations

import importlib
import sys
from typing import Callable


class LazyModule:
    """Stands for module `name` until an attribute is asked for; then imports it and
    takes over its namespace, so that later lookups cost what a module's do."""

    def __init__(self, name: str):
        self.__dict__["_lazy_name"] = name

    def __getattr__(self, attr: str):
        # only called for what the instance does not hold yet: the first lookup
        module = importlib.import_module(self.__dict__["_lazy_name"])
        self.__dict__.update(vars(module))
        return getattr(module, attr)

    def __repr__(self) -> str:
        return f"<lazy module {self.__dict__['_lazy_name']!r}>"


def lazy(name: str) -> LazyModule:
    """`name`, imported on its first attribute (see :class:`LazyModule`)."""
    return LazyModule(name)


def lazy_exports(package: str, where: dict[str, str],
                 computed: dict[str, Callable[[], object]] | None = None):
    """The PEP 562 ``__getattr__`` and ``__dir__`` of `package`, whose names are imported
    on first use: `where` maps each to the module that defines it (relative to the
    package), `computed` maps further names to the function that makes each. A name is
    looked up or made once, then kept in the package's namespace, so later lookups do not
    come back here. Call it from the package's ``__init__`` (it is then in sys.modules)."""
    computed = computed or {}
    namespace = sys.modules[package].__dict__

    def __getattr__(name: str):
        if name in computed:
            value = computed[name]()
        elif name in where:
            value = getattr(importlib.import_module(where[name], package), name)
        else:
            raise AttributeError(f"module '{package}' has no attribute '{name}'")
        namespace[name] = value
        return value

    def __dir__() -> list[str]:
        return sorted(set(namespace) | set(where) | set(computed))

    return __getattr__, __dir__
