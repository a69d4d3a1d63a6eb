"""Taking the animation elsewhere: a clip's skeleton and motion as BVH, glTF or USD.

- :mod:`.formats`: which suffixes are written;
- :mod:`.bvh`: the BVH writer;
- :mod:`.mesh`: the creature's mesh bound to the skeleton (shared by glTF and USD);
- :mod:`.gltf`: the binary glTF writer (skinned mesh, animation with root motion);
- :mod:`.usd`: UsdSkel stages (.usda, .usdc; needs the optional usd-core);
- :mod:`.clip`: ``gaitlab export`` (simulate as ``render`` does, then write).

The writers are imported on first use (they pull in scipy), so commands that only need
:mod:`.formats` (``gaitlab render``, ``--help``) start faster.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from .formats import EXPORT_FORMATS, export_format

if TYPE_CHECKING:
    from .bvh import bvh_text, write_bvh
    from .clip import ExportResult, export_cast, export_clip
    from .gltf import gltf_document, write_glb
    from .usd import write_usd

_HOMES = {"bvh_text": "bvh", "write_bvh": "bvh", "ExportResult": "clip", "export_clip": "clip", "export_cast": "clip",
          "gltf_document": "gltf", "write_glb": "gltf", "write_usd": "usd"}

__all__ = ["EXPORT_FORMATS", "ExportResult", "bvh_text", "export_cast", "export_clip", "export_format", "gltf_document",
           "write_bvh",
           "write_glb", "write_usd"]


def __getattr__(name: str) -> Any:
    home = _HOMES.get(name)
    if home is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{home}", __name__), name)
    globals()[name] = value
    return value
