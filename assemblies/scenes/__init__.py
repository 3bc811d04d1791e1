"""The named scenes: a registry built from one module per family.

The family modules import only :mod:`.scene` (what a scene is) and their own helpers,
never this registry, so imports go one way: registry -> families -> scene.

A family is imported when one of its scenes is asked for: :func:`scene` loads the one
family that :mod:`assemblies.scene_names` files the scene under (a family's references
load scipy, its plots matplotlib, a foreign controller pythonfmu; a run of another scene
needs none of them). ``SCENES``, the whole registry, imports every family on first use
(PEP 562); from then on :func:`scene` reads it, so a scene added to it is found.
"""
from __future__ import annotations

import importlib

from components.lazy import lazy_exports

from ..assembly import AssemblyError
from ..scene_names import SCENE_INDEX
from .scene import Figure, Scene

# family module -> the dict of scenes it defines, in the registry's order
FAMILIES = {"friction": "FRICTION_SCENES", "axle": "AXLE_SCENES", "coin": "COIN_SCENES",
            "beam": "BEAM_SCENES", "table": "TABLE_SCENES", "joined": "JOINED_SCENES",
            "speed_control": "SPEED_CONTROL_SCENES", "friction_seed": "SEED_FRICTION_SCENES",
            "bodies_seed": "SEED_BODY_SCENES", "bodies_exercises": "EXERCISE_SCENES",
            "sliding": "SLIDING_SCENES", "burridge_knopoff": "BURRIDGE_KNOPOFF_SCENES",
            "msl_translational": "MSL_TRANSLATIONAL_SCENES",
            "msl_rotational": "MSL_ROTATIONAL_SCENES",
            "msl_rotational_friction": "MSL_ROTATIONAL_FRICTION_SCENES",
            "msl_rotational_examples": "MSL_ROTATIONAL_EXAMPLE_SCENES"}


def family(module: str) -> dict[str, Scene]:
    """The scenes family `module` defines (imported now if it was not)."""
    return getattr(importlib.import_module(f".{module}", __name__), FAMILIES[module])


def _registry() -> dict[str, Scene]:
    return {name: sc for module in FAMILIES for name, sc in family(module).items()}


__getattr__, __dir__ = lazy_exports(__name__, {}, {"SCENES": _registry})


def scene(name: str) -> Scene:
    registry = globals().get("SCENES")
    if registry is None:  # the one family, not the registry (a test holds the index to it)
        found = family(SCENE_INDEX[name][0]).get(name) if name in SCENE_INDEX else None
        if found is None:
            raise AssemblyError(f"unknown scene '{name}'; scenes: {', '.join(SCENE_INDEX)}")
        return found
    if name not in registry:
        raise AssemblyError(f"unknown scene '{name}'; scenes: {', '.join(registry)}")
    return registry[name]


__all__ = ["FAMILIES", "Figure", "SCENES", "Scene", "family", "scene"]
