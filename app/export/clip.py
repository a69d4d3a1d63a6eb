"""``gaitlab export``: simulate a clip as ``render`` would and write it as skeletons:
one creature, or every creature of a scene (one skeleton each in a glTF or USD file; one
BVH file each)."""

from __future__ import annotations

import os
from dataclasses import dataclass
from functools import partial
from pathlib import Path

from ..cast import Actor, Cast, cast_motions
from ..errors import OutputError
from ..kinematics.skeleton import SkeletonClip, skeleton_clip
from ..kinematics.world import World
from ..limits import check_clip
from ..output import check_output_dir, write_together
from ..spec import CreatureSpec
from .bvh import bvh_text
from .formats import export_format
from .gltf import write_glb
from .mesh import export_layout
from .usd import write_usd


@dataclass(frozen=True)
class ExportResult:
    path: Path  # the file written (the first, for BVH files of a scene)
    frames: int
    joints: int  # in all skeletons
    seconds: float
    units: str = "metres, Y up"  # every format
    paths: tuple[Path, ...] = ()  # every file written (several BVH files for a scene)
    skeletons: int = 1


def export_clip(spec: CreatureSpec, output: str | os.PathLike[str], fps: float = 30.0, seconds: float | None = None,
                cycles: float | None = None, start: float = 0.0, speed: tuple[float, float] | None = None,
                world: World | None = None, loop: bool = False, ground: bool = False) -> ExportResult:
    """One creature's clip (see :func:`export_cast`)."""
    return export_cast((Actor(spec, world or World(), speed),), output, fps, seconds, cycles, start, loop, ground)


FILE_NAME_PART = 60  # characters of a creature's name put into a file name, at most


def file_name_part(name: str) -> str:
    """``name`` made safe as part of a file name: no folder separators, control
    characters or NULs (each becomes "_"), at most :data:`FILE_NAME_PART` characters."""
    safe = "".join("_" if c in '/\\' or not c.isprintable() else c for c in name).strip() or "creature"
    return safe[:FILE_NAME_PART]


def _unique(names: list[str]) -> list[str]:
    """``names`` with a second of a name made NAME-2 (a third NAME-3, ...)."""
    out: list[str] = []
    for name in names:
        candidate, count = name, 1
        while candidate in out:
            count += 1
            candidate = f"{name}-{count}"
        out.append(candidate)
    return out


def bvh_paths(output: str | os.PathLike[str], cast: Cast) -> list[Path]:
    """Where each creature's BVH goes: ``output`` itself for one creature; for several,
    ``STEM-NAME.bvh`` beside it (``STEM-NAME-2.bvh`` for a second of the same name; the
    name made safe for a file name by :func:`file_name_part`)."""
    output = Path(output)
    if len(cast) == 1:
        return [output]
    names = _unique([file_name_part(actor.spec.name) for actor in cast])  # a second dog, a dog after one named dog-2
    return [output.with_name(f"{output.stem}-{name}{output.suffix}") for name in names]


def load_model_joints(path: str) -> tuple[str, ...]:
    """The joint names of the rigged model at ``path``."""
    from ..rigged.loaded import load_model

    return load_model(path).model.names


def export_cast(cast: Cast, output: str | os.PathLike[str], fps: float = 30.0, seconds: float | None = None,
                cycles: float | None = None, start: float = 0.0, loop: bool = False,
                ground: bool = False) -> ExportResult:
    """Simulate the cast (as ``gaitlab render`` does) and write its skeletons to
    ``output`` (format by suffix). ``loop``: whole cycles with the closing frame (last =
    first). Checks the output before simulating; writes atomically; raises
    :class:`GaitlabError` with one line for bad input."""
    fmt = export_format(output)
    check_output_dir(output)
    if fmt == "bvh":
        for path in bvh_paths(output, cast):  # each creature's file, before anything is simulated
            check_output_dir(path)
    model = cast[0].spec.source if cast[0].spec.source.lower().endswith((".glb", ".gltf")) else ""
    if model and (fmt != "glb" or len(cast) > 1 or ground):
        raise OutputError(f"{os.fspath(output)}: a rigged model is exported alone, on its own skeleton, as .glb "
                          "(without --ground)")
    if fmt in ("usda", "usdc"):
        from .usd import _pxr

        _pxr()  # usd-core installed? (say so before simulating)
    speeds = [actor.speed for actor in cast]
    for speed in speeds:
        check_clip(fps, seconds, cycles, start, speed)
    if loop and (seconds is not None or any(speeds)):
        raise OutputError("a looped export is whole cycles whose last frame equals the first: give a length in "
                          "cycles, without seconds or a speed")
    if loop and cycles is not None and (cycles < 1 or abs(cycles - round(cycles)) > 1e-9):
        raise OutputError(f"--cycles {cycles:g} with --loop: a loop is whole cycles whose last frame equals the "
                          "first; give 1, 2, 3, ...")
    if ground and fmt != "glb":
        raise OutputError(f"--ground adds the terrain as a mesh to glTF files; write .glb (not .{fmt})")
    if ground and any(actor.world.in_place for actor in cast):
        raise OutputError("--ground: an in-place clip's ground moves under the feet; export it travelling "
                          "(without --in-place)")
    if cycles is None and seconds is None:
        cycles = None if speeds[0] is not None else 2.0
        seconds = 4.0 if speeds[0] is not None else None
    motions, _ = cast_motions(cast, fps, seconds, cycles, start, closed=loop)
    if motions[0].frame_count == 0:
        raise OutputError(f"{os.fspath(output)}: the clip has no frames at {fps:g} fps; give a longer --seconds "
                          "or --cycles")
    # A mesh-carrying file lays its skeletons out as their bodies are (so they skin as drawn).
    clips: list[SkeletonClip] = [skeleton_clip(m, None if fmt == "bvh" else export_layout(m)) for m in motions]
    seconds_out = (clips[0].frame_count - int(loop)) / fps  # a looped clip's closing frame adds no time
    names = _unique([actor.spec.name for actor in cast])  # the skeletons' names in one .glb or USD stage
    if fmt == "bvh":
        paths = bvh_paths(output, cast)
        texts = [bvh_text(c) for c in clips]
        write_together([(p, partial(Path.write_text, data=t, encoding="utf-8"))
                        for p, t in zip(paths, texts)])  # every creature's file, or none
    elif model:
        from .model import write_model_glb

        paths = [write_model_glb(motions[0], output, fps)]
        return ExportResult(Path(paths[0]), clips[0].frame_count, len(load_model_joints(model)), seconds_out,
                            units="the model's own units and axes", paths=(Path(paths[0]),), skeletons=1)
    elif fmt == "glb":
        paths = [write_glb(output, motions, clips, ground=ground, names=names if len(cast) > 1 else None)]
    else:
        paths = [write_usd(output, motions, clips, names=names)]
    return ExportResult(Path(paths[0]), clips[0].frame_count, sum(c.skeleton.count for c in clips), seconds_out,
                        paths=tuple(Path(p) for p in paths), skeletons=len(clips))
