"""Setting uniforms only when they change (a software renderer validates programs on
every change, so unchanged values are skipped)."""

from __future__ import annotations

from typing import Any

import moderngl
from pyglm import glm


class Uniforms:
    """Remembers every program's uniform names and last values; :meth:`set` writes a
    value only when the program has that uniform and the value changed."""

    def __init__(self) -> None:
        self._members: dict[int, set[str]] = {}
        self._values: dict[tuple[int, str], Any] = {}

    def set(self, prog: moderngl.Program, name: str, value: Any) -> None:
        members = self._members.get(prog.glo)
        if members is None:
            members = self._members[prog.glo] = {m for m in prog if isinstance(prog[m], moderngl.Uniform)}
        if name not in members:
            return
        key = (prog.glo, name)
        if self._values.get(key) == value:
            return
        self._values[key] = value
        member = uniform(prog, name)
        if isinstance(value, glm.mat4):
            member.write(value)
        else:
            member.value = value


def uniform(prog: moderngl.Program, name: str) -> moderngl.Uniform:
    """``prog[name]`` as the uniform it is (moderngl types the lookup as any member)."""
    member = prog[name]
    assert isinstance(member, moderngl.Uniform), f"{name} is not a uniform of the program"
    return member
