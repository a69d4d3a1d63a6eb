"""Acclaim ASF/AMC (HDM05's format) to BVH, for the corpus's HDM05 takes (kept for the record).

    python tests/data/corpus/acclaim_to_bvh.py SKELETON.asf MOTION.amc OUT.bvh [SCALE]

Acclaim's rules: each bone's rotation in the AMC is about its own ``axis`` frame C, so
its local rotation is C M C^-1; the rest pose is world-aligned, each bone reaching
``direction * length`` from its parent's end. The BVH gets the same hierarchy (the
root's children at the root, each bone's end an End Site or its children's offset),
Z-Y-X Euler channels and ``SCALE`` times the ASF's units (HDM05: 5.6444 gives
centimetres, an ASF unit being 1/0.45 inches). Frames at 120 per second.
"""

from __future__ import annotations

import math
import re
import sys
from pathlib import Path

import numpy as np


def axis_rotation(axis: str, degrees: float) -> np.ndarray:
    a = math.radians(degrees)
    c, s = math.cos(a), math.sin(a)
    if axis == "x":
        return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    if axis == "y":
        return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def euler(order: str, angles: list[float]) -> np.ndarray:
    """The rotation applying ``order``'s axes in turn (``"xyz"``: x first, R = Rz Ry Rx)."""
    rotation = np.eye(3)
    for axis, angle in zip(order, angles):
        rotation = axis_rotation(axis, angle) @ rotation
    return rotation


def zyx_degrees(r: np.ndarray) -> list[float]:
    """Z, Y, X angles (degrees) with r = Rz Ry Rx."""
    y = math.asin(max(-1.0, min(1.0, -r[2, 0])))
    if abs(r[2, 0]) < 0.999999:
        z, x = math.atan2(r[1, 0], r[0, 0]), math.atan2(r[2, 1], r[2, 2])
    else:
        z, x = math.atan2(-r[0, 1], r[1, 1]), 0.0
    return [math.degrees(z), math.degrees(y), math.degrees(x)]


def read_asf(path: Path) -> tuple[dict[str, dict], dict[str, list[str]], list[str]]:
    """Bones (name -> direction, length, axis angles and order, dofs), the hierarchy
    (parent -> children) and the root's channel order."""
    bones: dict[str, dict] = {}
    children: dict[str, list[str]] = {}
    root_order: list[str] = []
    section, bone = "", None
    for line in path.read_text(encoding="latin-1").splitlines():
        words = line.split()
        if not words:
            continue
        if words[0].startswith(":"):
            section = words[0]
        elif section == ":root" and words[0] == "order":
            root_order = [w.lower() for w in words[1:]]
        elif section == ":bonedata":
            if words[0] == "begin":
                bone = {"dof": []}
            elif words[0] == "end" and bone is not None:
                bones[bone["name"]] = bone
                bone = None
            elif bone is not None:
                key = words[0]
                if key == "name":
                    bone["name"] = words[1]
                elif key == "direction":
                    bone["direction"] = np.array([float(w) for w in words[1:4]])
                elif key == "length":
                    bone["length"] = float(words[1])
                elif key == "axis":
                    bone["axis"] = ([float(w) for w in words[1:4]], words[4].lower())
                elif key == "dof":
                    bone["dof"] = [w.lower() for w in words[1:]]
        elif section == ":hierarchy" and words[0] not in ("begin", "end"):
            children[words[0]] = words[1:]
    return bones, children, root_order


def read_amc(path: Path) -> list[dict[str, list[float]]]:
    frames: list[dict[str, list[float]]] = []
    for line in path.read_text(encoding="latin-1").splitlines():
        line = line.strip()
        if not line or line.startswith(("#", ":")):
            continue
        if re.fullmatch(r"\d+", line):
            frames.append({})
        else:
            words = line.split()
            frames[-1][words[0]] = [float(w) for w in words[1:]]
    return frames


def convert(asf: Path, amc: Path, scale: float = 1.0) -> str:
    bones, children, root_order = read_asf(asf)
    frames = read_amc(amc)
    order: list[str] = []
    parent: dict[str, str | None] = {}

    def visit(name: str, up: str | None) -> None:
        order.append(name)
        parent[name] = up
        for child in children.get(name, []):
            visit(child, name)

    visit("root", None)
    frame_of = {n: euler(bones[n]["axis"][1], bones[n]["axis"][0]) for n in order[1:]}
    lines = ["HIERARCHY"]

    def write(name: str, depth: int) -> None:
        pad = "  " * depth
        if name == "root":
            lines.extend(["ROOT root", "{", "  OFFSET 0 0 0",
                          "  CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation"])
        else:
            up = parent[name]
            offset = np.zeros(3) if up == "root" else bones[up]["direction"] * bones[up]["length"] * scale
            lines.extend([f"{pad}JOINT {name}", f"{pad}{{", f"{pad}  OFFSET " + " ".join(f"{v:.6f}" for v in offset),
                          f"{pad}  CHANNELS 3 Zrotation Yrotation Xrotation"])
            if not children.get(name):
                end = bones[name]["direction"] * bones[name]["length"] * scale
                lines.extend([f"{pad}  End Site", f"{pad}  {{", f"{pad}    OFFSET " + " ".join(f"{v:.6f}" for v in end),
                              f"{pad}  }}"])
        for child in children.get(name, []):
            write(child, depth + 1)
        lines.append(f"{pad}}}")

    write("root", 0)
    lines += ["MOTION", f"Frames: {len(frames)}", f"Frame Time: {1 / 120:.8f}"]
    rotation_order = "".join(c[1] for c in root_order if c.startswith("r"))
    for frame in frames:
        root = dict(zip(root_order, frame["root"]))
        row = [root.get(f"t{a}", 0.0) * scale for a in "xyz"]
        row += zyx_degrees(euler(rotation_order, [root["r" + a] for a in rotation_order]))
        for name in order[1:]:
            dof = dict(zip(bones[name]["dof"], frame.get(name, [0.0] * len(bones[name]["dof"]))))
            axes = bones[name]["axis"][1]
            local = frame_of[name] @ euler(axes, [dof.get("r" + a, 0.0) for a in axes]) @ frame_of[name].T
            row += zyx_degrees(local)
        lines.append(" ".join(f"{v:.6f}" for v in row))
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    asf_path, amc_path, out_path = (Path(a) for a in sys.argv[1:4])
    out_path.write_text(convert(asf_path, amc_path, float(sys.argv[4]) if len(sys.argv) > 4 else 1.0))
