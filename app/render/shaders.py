"""Loading GLSL programs from ``shaders/`` by name, with ``#include "file.glsl"``."""

from __future__ import annotations

import re

import moderngl

from ..resources import shaders_dir

_INCLUDE = re.compile(r'^\s*#include\s+"([^"]+)"\s*$', re.MULTILINE)


def shader_source(name: str, _seen: tuple[str, ...] = ()) -> str:
    """The text of ``shaders/<name>`` with its includes expanded (each file once)."""
    if name in _seen:
        raise ValueError(f"shader include cycle: {' -> '.join(_seen + (name,))}")
    text = (shaders_dir() / name).read_text(encoding="utf-8")
    return _INCLUDE.sub(lambda m: shader_source(m.group(1), _seen + (name,)), text)


def with_defines(source: str, defines: tuple[str, ...]) -> str:
    """``source`` with ``#define NAME`` lines after its ``#version`` line."""
    if not defines:
        return source
    first, _, rest = source.partition("\n")
    return "\n".join([first, *(f"#define {name}" for name in defines), rest])


class ShaderLibrary:
    """Programs of one context, compiled once per (vertex, fragment) pair, each with
    ``defines`` (names the shaders test with ``#ifdef``: a renderer's quality choices)."""

    def __init__(self, ctx: moderngl.Context, defines: tuple[str, ...] = ()) -> None:
        self.ctx = ctx
        self.defines = defines
        self._programs: dict[tuple[str, str], moderngl.Program] = {}

    def program(self, vertex: str, fragment: str) -> moderngl.Program:
        """The program linking ``shaders/<vertex>`` and ``shaders/<fragment>``."""
        key = (vertex, fragment)
        if key not in self._programs:
            self._programs[key] = self.ctx.program(
                vertex_shader=with_defines(shader_source(vertex), self.defines),
                fragment_shader=with_defines(shader_source(fragment), self.defines))
        return self._programs[key]

    def release(self) -> None:
        for program in self._programs.values():
            program.release()
        self._programs.clear()
