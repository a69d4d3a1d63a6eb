"""Where creatures walk: paths and terrains from text and files, and scene files.

- :mod:`.kinds`: the one registry of path and terrain kinds and their keys (a leaf: the
  command line's help reads it without loading the rest);
- :mod:`.text`: ``--path`` / ``--terrain`` text to paths, terrains and worlds;
- :mod:`.files`: heightmap images and meshes as ground;
- :mod:`.file`: scene TOML files (what a clip films of them: :mod:`app.cast`).

Names are imported from their modules on first use.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .file import Scene, SceneCreature, load_scene, scene_description
    from .files import load_heightmap, load_mesh_terrain
    from .kinds import FAR, PATH_KINDS, TERRAIN_KINDS
    from .text import make_world, parse_path, parse_terrain, waypoint_path

_HOMES = {"Scene": "file", "SceneCreature": "file", "load_scene": "file", "scene_description": "file",
          "load_heightmap": "files", "load_mesh_terrain": "files", "FAR": "kinds", "PATH_KINDS": "kinds",
          "TERRAIN_KINDS": "kinds", "make_world": "text", "parse_path": "text", "parse_terrain": "text",
          "waypoint_path": "text"}

__all__ = ["FAR", "PATH_KINDS", "TERRAIN_KINDS", "Scene", "SceneCreature", "load_heightmap", "load_mesh_terrain",
           "load_scene", "make_world", "parse_path", "parse_terrain", "scene_description", "waypoint_path"]


def __getattr__(name: str) -> Any:
    home = _HOMES.get(name)
    if home is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{home}", __name__), name)
    globals()[name] = value
    return value
