"""``gaitlab export``: simulate a clip as ``render`` would and write it as a skeleton."""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from ..errors import OutputError
from ..limits import check_clip
from ..kinematics.clip import clip_motion
from ..kinematics.skeleton import skeleton_clip
from ..kinematics.world import World
from ..output import check_output_dir
from ..rigging import build_rig
from ..spec import CreatureSpec
from .bvh import write_bvh
from .formats import export_format
from .gltf import write_glb
from .usd import write_usd


@dataclass(frozen=True)
class ExportResult:
    path: Path
    frames: int
    joints: int
    seconds: float
    units: str = "metres, Y up"  # both formats


def export_clip(spec: CreatureSpec, output: str | os.PathLike[str], fps: float = 30.0, seconds: float | None = None,
                cycles: float | None = None, start: float = 0.0, speed: tuple[float, float] | None = None,
                world: World | None = None, loop: bool = False, ground: bool = False) -> ExportResult:
    """Simulate ``spec`` (as ``gaitlab render`` does) and write the skeleton to ``output``
    (format by suffix). ``loop``: whole cycles with the closing frame (last = first).
    Checks the output before simulating; writes atomically; raises
    :class:`GaitlabError` with one line for bad input."""
    fmt = export_format(output)
    check_output_dir(output)
    if fmt in ("usda", "usdc"):
        from .usd import _pxr

        _pxr()  # usd-core installed? (say so before simulating)
    check_clip(fps, seconds, cycles, start, speed)
    if loop and (seconds is not None or speed is not None):
        raise OutputError("a looped export is whole cycles whose last frame equals the first: give a length in "
                          "cycles, without seconds or a speed")
    if ground and fmt != "glb":
        raise OutputError(f"--ground adds the terrain as a mesh to glTF files; write .glb (not .{fmt})")
    if ground and world is not None and world.in_place:
        raise OutputError("--ground: an in-place clip's ground moves under the feet; export it travelling "
                          "(without --in-place)")
    if cycles is None and seconds is None:
        cycles = None if speed is not None else 2.0
        seconds = 4.0 if speed is not None else None
    rig = build_rig(spec)
    motion, _ = clip_motion(rig, fps, seconds, cycles, start, speed, world=world or World(), closed=loop)
    if motion.frame_count == 0:
        raise OutputError(f"{os.fspath(output)}: the clip has no frames at {fps:g} fps; give a longer --seconds "
                          "or --cycles")
    clip = skeleton_clip(motion)
    seconds_out = (clip.frame_count - int(loop)) / fps  # a looped clip's closing frame adds no time
    if fmt == "bvh":
        path = write_bvh(output, clip)
    elif fmt == "glb":
        path = write_glb(output, motion, clip, ground=ground)
    else:
        path = write_usd(output, motion, clip)
    return ExportResult(Path(path), clip.frame_count, clip.skeleton.count, seconds_out)
