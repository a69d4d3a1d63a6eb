"""Reading BVH motion capture and computing joint positions (forward kinematics).

Written here rather than taken from a library because the clips Gaitlab is tested on put
position channels on every joint (they *replace* the joint's OFFSET), which common BVH
readers refuse, and because every parse error must name the file and line.
Forward kinematics is vectorised over frames; it walks only the chain of joints that lead
to the ones asked for.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from ..errors import GaitlabError

_AXES = {"X": 0, "Y": 1, "Z": 2}
_WHOLE = re.compile(r"[0-9]{1,12}")  # ASCII digits only ("²".isdigit() is True)
MAX_FILE_BYTES = 512 * 2**20
MAX_JOINTS = 10_000
MAX_CHANNELS_PER_JOINT = 9
MIN_FRAME_TIME = 1e-4  # s: a BVH or CSV clip sampled faster than 10 kHz is no capture (and breaks the maths)


class InputError(GaitlabError):
    """A motion file that cannot be read (syntax, truncation, missing columns, ...)."""


@dataclass
class BvhJoint:
    name: str
    parent: int  # index into BvhClip.joints, -1 for the root
    offset: NDArray[np.float64]
    channels: list[str] = field(default_factory=list)
    first_channel: int = 0  # column of its first channel in the frame data
    end_site: bool = False  # an End Site: the tip of its parent's bone, named PARENT/End, no channels


@dataclass
class BvhClip:
    """A parsed BVH file: joints in file order, frames (T, channels), frame time (s)."""

    path: str
    joints: list[BvhJoint]
    frames: NDArray[np.float64]
    frame_time: float

    @property
    def names(self) -> list[str]:
        return [j.name for j in self.joints]

    def index(self, name: str) -> int:
        for i, joint in enumerate(self.joints):
            if joint.name == name:
                return i
        raise KeyError(name)

    def positions(self, names: list[str]) -> NDArray[np.float64]:
        """World positions (T, len(names), 3) of the named joints, in file units and axes
        (inf or NaN where a file's numbers overflow: the callers check, numpy does not warn)."""
        with np.errstate(over="ignore", invalid="ignore"):
            return self._positions(names)

    def _positions(self, names: list[str]) -> NDArray[np.float64]:
        wanted = [self.index(n) for n in names]
        needed: set[int] = set()
        for i in wanted:
            while i >= 0 and i not in needed:
                needed.add(i)
                i = self.joints[i].parent
        frames = self.frames.shape[0]
        rotation: dict[int, NDArray] = {}
        position: dict[int, NDArray] = {}
        for i in sorted(needed):  # parents come before children in file order
            joint = self.joints[i]
            local_r = np.broadcast_to(np.eye(3), (frames, 3, 3))
            local_t = np.broadcast_to(joint.offset, (frames, 3)).copy()
            for k, channel in enumerate(joint.channels):
                values = self.frames[:, joint.first_channel + k]
                axis = _AXES[channel[0].upper()]
                if channel[1:].lower() == "position":
                    local_t[:, axis] = values  # position channels replace the OFFSET
                else:
                    local_r = local_r @ _axis_rotation(axis, np.radians(values))
            if joint.parent < 0:
                rotation[i], position[i] = local_r, local_t
            else:
                parent_r = rotation[joint.parent]
                position[i] = position[joint.parent] + np.einsum("tij,tj->ti", parent_r, local_t)
                rotation[i] = parent_r @ local_r
        return np.stack([position[i] for i in wanted], axis=1)


def _axis_rotation(axis: int, angles: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rotation matrices (T, 3, 3) about one coordinate axis."""
    c, s = np.cos(angles), np.sin(angles)
    m = np.zeros(angles.shape + (3, 3))
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    m[:, axis, axis] = 1.0
    m[:, i, i] = c
    m[:, j, j] = c
    m[:, i, j] = -s
    m[:, j, i] = s
    return m


def _shown(token: str, limit: int = 40) -> str:
    """A token for an error message: quoted, and cut short if long."""
    return repr(token if len(token) <= limit else token[:limit] + "...")


class _Tokens:
    """Whitespace tokens with their line numbers."""

    def __init__(self, path: str, lines: list[str]) -> None:
        self.path = path
        self.items = [(tok, n + 1) for n, line in enumerate(lines) for tok in line.split()]
        self.pos = 0

    def error(self, message: str, line: int | None = None) -> InputError:
        if line is None:
            line = self.items[min(self.pos, len(self.items) - 1)][1] if self.items else 1
        return InputError(f"{self.path}:{line}: malformed BVH: {message}")

    def next(self, what: str) -> tuple[str, int]:
        if self.pos >= len(self.items):
            last = self.items[-1][1] if self.items else 1
            raise InputError(f"{self.path}:{last}: truncated BVH: the file ends where {what} was expected")
        item = self.items[self.pos]
        self.pos += 1
        return item

    def expect(self, word: str) -> int:
        tok, line = self.next(repr(word))
        if tok.upper() != word.upper():
            raise self.error(f"expected {word!r}, found {_shown(tok)}", line)
        return line

    def number(self, what: str) -> float:
        tok, line = self.next(what)
        try:
            value = float(tok)
        except ValueError:
            raise self.error(f"{what}: {_shown(tok)} is not a number", line) from None
        if not math.isfinite(value):
            raise self.error(f"{what}: {_shown(tok)} is not a finite number", line)
        return value


def read_bvh(path: str | os.PathLike[str]) -> BvhClip:
    """Parse a BVH file. Raises :class:`InputError` naming the file and line."""
    path = os.fspath(path)
    lines = _read_lines(path)
    try:
        motion_at = next(i for i, line in enumerate(lines) if line.strip().upper() == "MOTION")
    except StopIteration:
        raise InputError(f"{path}:{len(lines)}: truncated BVH: no MOTION section") from None
    joints = _hierarchy(_Tokens(path, lines[:motion_at]))
    channel_count = sum(len(j.channels) for j in joints)
    frames, frame_time = _motion(path, lines, motion_at, channel_count)
    return BvhClip(path=path, joints=joints, frames=frames, frame_time=frame_time)


def _read_lines(path: str) -> list[str]:
    """The file's lines, read whole up to the size limit."""
    try:
        with open(path, "rb") as fh:
            raw = fh.read(MAX_FILE_BYTES + 1)  # not stat(): pipes and /proc files say 0
        if len(raw) > MAX_FILE_BYTES:
            raise InputError(f"{path}: the file is over {MAX_FILE_BYTES // 2**20} MiB; BVH files up to that "
                             "size are read")
        return raw.decode("utf-8", errors="replace").splitlines()
    except OSError as exc:
        raise InputError(f"{path}: cannot read: {exc.strerror or exc}") from None


def _hierarchy(tokens: _Tokens) -> list[BvhJoint]:
    """The joints of the HIERARCHY section, in file order (a stack, no recursion: any depth)."""
    tokens.expect("HIERARCHY")
    joints: list[BvhJoint] = []
    tok, line = tokens.next("ROOT")
    if tok.upper() != "ROOT":
        raise tokens.error(f"expected ROOT, found {_shown(tok)}", line)
    stack = [_joint(tokens, joints, -1)]  # the open joints, innermost last
    while stack:
        tok, line = tokens.next("JOINT, End Site or '}'")
        if tok.upper() == "JOINT":
            stack.append(_joint(tokens, joints, stack[-1]))
        elif tok.upper() == "END":
            tokens.expect("Site")
            tokens.expect("{")
            tokens.expect("OFFSET")
            tip = np.array([tokens.number(f"End Site OFFSET {axis}") for axis in "xyz"])
            tokens.expect("}")
            parent = stack[-1]
            after = joints[-1].first_channel + len(joints[-1].channels)  # no channels of its own
            joints.append(BvhJoint(name=f"{joints[parent].name}/End", parent=parent, offset=tip, first_channel=after,
                                   end_site=True))
        elif tok == "}":
            stack.pop()
        else:
            raise tokens.error(f"expected JOINT, End Site or '}}', found {_shown(tok)}", line)
    if tokens.pos < len(tokens.items):
        tok, line = tokens.items[tokens.pos]
        raise tokens.error(f"unexpected {_shown(tok)} after the hierarchy", line)
    return joints


def _joint(tokens: _Tokens, joints: list[BvhJoint], parent: int) -> int:
    """The joint header (name, OFFSET, CHANNELS) after a ROOT/JOINT keyword, appended to
    ``joints``; its index."""
    name, _ = tokens.next("a joint name")
    tokens.expect("{")
    tokens.expect("OFFSET")
    offset = np.array([tokens.number("OFFSET x"), tokens.number("OFFSET y"), tokens.number("OFFSET z")])
    tokens.expect("CHANNELS")
    count_tok, count_line = tokens.next("the channel count")
    if not _WHOLE.fullmatch(count_tok) or int(count_tok) > MAX_CHANNELS_PER_JOINT:
        raise tokens.error(f"channel count {_shown(count_tok)}: expected a whole number from 0 to "
                           f"{MAX_CHANNELS_PER_JOINT}", count_line)
    channels = []
    for _ in range(int(count_tok)):
        ch, ch_line = tokens.next("a channel name")
        if len(ch) < 2 or ch[0].upper() not in _AXES or ch[1:].lower() not in ("position", "rotation"):
            raise tokens.error(f"unknown channel {_shown(ch)} (expected Xposition ... Zrotation)", ch_line)
        channels.append(ch)
    if len(joints) >= MAX_JOINTS:
        raise tokens.error(f"more than {MAX_JOINTS} joints")
    first_channel = joints[-1].first_channel + len(joints[-1].channels) if joints else 0
    joints.append(BvhJoint(name, parent, offset, channels, first_channel))
    return len(joints) - 1


def _motion(path: str, lines: list[str], motion_at: int, channel_count: int) -> tuple[NDArray[np.float64], float]:
    """The MOTION section: frames (T, channels) and the frame time (s)."""
    header = [(n, lines[n].strip()) for n in range(motion_at + 1, min(motion_at + 3, len(lines)))]
    if len(header) < 2:
        raise InputError(f"{path}:{len(lines)}: truncated BVH: the MOTION section has no Frames / Frame Time lines")
    frames_label, _, frames_text = header[0][1].partition(":")
    if frames_label.strip().lower() != "frames" or not _WHOLE.fullmatch(frames_text.strip()):
        raise InputError(f"{path}:{header[0][0] + 1}: malformed BVH: expected 'Frames: N' (a whole number), found "
                         f"{header[0][1][:80]!r}")
    frame_count = int(frames_text.strip())
    time_label, _, time_text = header[1][1].partition(":")
    try:
        frame_time = float(time_text)
    except ValueError:
        frame_time = math.nan
    if time_label.strip().lower() != "frame time" or not (MIN_FRAME_TIME <= frame_time < 3600):
        raise InputError(f"{path}:{header[1][0] + 1}: malformed BVH: expected 'Frame Time: seconds' (at least "
                         f"{MIN_FRAME_TIME:g}, a {1 / MIN_FRAME_TIME:,.0f} Hz capture, and less than an hour), found "
                         f"{header[1][1][:80]!r}")
    first = motion_at + 3
    data_lines = [(n, line) for n, line in enumerate(lines[first:], start=first + 1) if line.strip()]
    if len(data_lines) < frame_count:
        end = data_lines[-1][0] if data_lines else first
        raise InputError(f"{path}:{end}: truncated BVH: 'Frames: {frame_count}' but only {len(data_lines)} frame "
                         "lines follow")
    data_lines = data_lines[:frame_count]
    try:
        values = np.array(" ".join(line for _, line in data_lines).split(), dtype=np.float64)
    except ValueError:
        values = np.zeros(0)
    if values.size != frame_count * channel_count:
        _first_bad_line(path, data_lines, channel_count)
    frames = values.reshape(frame_count, channel_count)
    if not np.isfinite(frames).all():
        bad = int(np.nonzero(~np.isfinite(frames).all(axis=1))[0][0])
        raise InputError(f"{path}:{data_lines[bad][0]}: malformed BVH: frame holds a NaN or infinite value")
    return frames, frame_time


def _first_bad_line(path: str, data_lines: list[tuple[int, str]], channel_count: int) -> None:
    """Raise :class:`InputError` for the first frame line with the wrong count of values
    or a value that is not a number."""
    for line_number, text in data_lines:
        parts = text.split()
        if len(parts) != channel_count:
            raise InputError(f"{path}:{line_number}: malformed BVH: frame has {len(parts)} values, the hierarchy "
                             f"has {channel_count} channels")
        for k, part in enumerate(parts):
            try:
                float(part)
            except ValueError:
                raise InputError(f"{path}:{line_number}: malformed BVH: value {k + 1} ({_shown(part)}) is not a "
                                 "number") from None
    raise InputError(f"{path}: malformed BVH: the frames hold {sum(len(t.split()) for _, t in data_lines)} values "
                     f"for {len(data_lines)} frames of {channel_count} channels")
