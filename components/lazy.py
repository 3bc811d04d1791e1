"""A module that is imported when first used, not when its importer is.

CasADi takes 0.1-0.3 s to load and the components use it only to write their equations
(``equations()``, flattening, code generation): a run of FMUs already in the cache,
``mechfmu show`` and ``mechfmu components`` never need it. ``ca = lazy("casadi")`` at the
top of a module keeps ``ca.SX``, ``ca.if_else`` ... as they read, and loads CasADi on the
first such attribute.
"""
from __future__ import annotations

import importlib


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
