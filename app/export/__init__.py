"""Taking the animation elsewhere: a clip's skeleton and motion as BVH, glTF or USD.

- :mod:`.formats`: which suffixes are written;
- :mod:`.bvh`: the BVH writer;
- :mod:`.mesh`: the creature's mesh bound to the skeleton (shared by glTF and USD);
- :mod:`.gltf`: the binary glTF writer (skinned mesh, animation with root motion);
- :mod:`.usd`: UsdSkel stages (.usda, .usdc; needs the optional usd-core);
- :mod:`.clip`: ``gaitlab export`` (simulate as ``render`` does, then write).
"""

from .bvh import bvh_text, write_bvh
from .clip import ExportResult, export_clip
from .formats import EXPORT_FORMATS, export_format
from .gltf import gltf_document, write_glb
from .usd import write_usd

__all__ = ["EXPORT_FORMATS", "ExportResult", "bvh_text", "export_clip", "export_format", "gltf_document", "write_bvh",
           "write_glb", "write_usd"]
