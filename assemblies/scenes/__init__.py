"""The named scenes: a registry built from one module per family.

The family modules import only :mod:`.scene` (what a scene is) and their own helpers,
never this registry, so imports go one way: registry -> families -> scene.
"""
from __future__ import annotations

from ..assembly import AssemblyError
from .axle import AXLE_SCENES
from .beam import BEAM_SCENES
from .bodies_seed import SEED_BODY_SCENES
from .coin import COIN_SCENES
from .friction import FRICTION_SCENES
from .friction_seed import SEED_FRICTION_SCENES
from .joined import JOINED_SCENES
from .scene import Figure, Scene
from .speed_control import SPEED_CONTROL_SCENES
from .table import TABLE_SCENES

SCENES: dict[str, Scene] = {**FRICTION_SCENES, **AXLE_SCENES, **COIN_SCENES, **BEAM_SCENES,
                            **TABLE_SCENES, **JOINED_SCENES, **SPEED_CONTROL_SCENES,
                            **SEED_FRICTION_SCENES, **SEED_BODY_SCENES}


def scene(name: str) -> Scene:
    if name not in SCENES:
        raise AssemblyError(f"unknown scene '{name}'; scenes: {', '.join(SCENES)}")
    return SCENES[name]


__all__ = ["Figure", "SCENES", "Scene", "scene"]
