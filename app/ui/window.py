"""The glfw window: an OpenGL 3.3 core context, vsync, HiDPI, and input forwarded to ImGui.

glfw is imported here (before imgui_bundle, which bundles its own glfw library) and
nowhere on the headless path.
"""

from __future__ import annotations

import ctypes
import os
import sys

import glfw
from imgui_bundle import imgui

from ..errors import GaitlabError

NO_DISPLAY_HINT = ("no display to open a window on (DISPLAY is not set); run it under a virtual display with "
                   "'xvfb-run gaitlab view', or render headless with 'gaitlab render'")


def _key_map() -> dict[int, imgui.Key]:
    keys: dict[int, imgui.Key] = {}
    for i in range(26):
        keys[glfw.KEY_A + i] = getattr(imgui.Key, chr(ord("a") + i))
    for i in range(10):
        keys[glfw.KEY_0 + i] = getattr(imgui.Key, f"_{i}")
        keys[glfw.KEY_KP_0 + i] = getattr(imgui.Key, f"keypad{i}")
    for i in range(12):
        keys[glfw.KEY_F1 + i] = getattr(imgui.Key, f"f{i + 1}")
    named = {
        "TAB": "tab", "LEFT": "left_arrow", "RIGHT": "right_arrow", "UP": "up_arrow", "DOWN": "down_arrow",
        "PAGE_UP": "page_up", "PAGE_DOWN": "page_down", "HOME": "home", "END": "end", "INSERT": "insert",
        "DELETE": "delete", "BACKSPACE": "backspace", "SPACE": "space", "ENTER": "enter", "ESCAPE": "escape",
        "KP_ENTER": "keypad_enter", "KP_DECIMAL": "keypad_decimal", "KP_SUBTRACT": "keypad_subtract",
        "KP_ADD": "keypad_add", "LEFT_CONTROL": "left_ctrl", "RIGHT_CONTROL": "right_ctrl",
        "LEFT_SHIFT": "left_shift", "RIGHT_SHIFT": "right_shift", "LEFT_ALT": "left_alt", "RIGHT_ALT": "right_alt",
        "LEFT_SUPER": "left_super", "RIGHT_SUPER": "right_super", "MINUS": "minus", "EQUAL": "equal",
        "PERIOD": "period", "COMMA": "comma", "SLASH": "slash", "SEMICOLON": "semicolon",
        "APOSTROPHE": "apostrophe", "LEFT_BRACKET": "left_bracket", "RIGHT_BRACKET": "right_bracket",
        "BACKSLASH": "backslash", "GRAVE_ACCENT": "grave_accent",
    }
    for glfw_name, imgui_name in named.items():
        keys[getattr(glfw, f"KEY_{glfw_name}")] = getattr(imgui.Key, imgui_name)
    return keys


_MODIFIERS = {
    imgui.Key.left_ctrl: imgui.Key.mod_ctrl, imgui.Key.right_ctrl: imgui.Key.mod_ctrl,
    imgui.Key.left_shift: imgui.Key.mod_shift, imgui.Key.right_shift: imgui.Key.mod_shift,
    imgui.Key.left_alt: imgui.Key.mod_alt, imgui.Key.right_alt: imgui.Key.mod_alt,
    imgui.Key.left_super: imgui.Key.mod_super, imgui.Key.right_super: imgui.Key.mod_super,
}


def software_gl_threads(environ: dict[str, str] | os._Environ[str] = os.environ, cores: int | None = None) -> None:
    """Give Mesa's software rasteriser (llvmpipe) one thread more than the machine has
    cores, unless ``LP_NUM_THREADS`` is set already (a GPU's driver ignores it).

    The viewer's main thread (Python: the motion, the UI, issuing the GL) runs beside the
    rasteriser's threads. With one rasteriser thread per core, the core the main thread
    shares holds up the end of every pass: the tiles are shared out among threads, and
    the last tile of that core's thread waits for its share of the core. With one thread
    more, the tiles even out around the main thread: the viewer ran 9 % faster on two
    cores (median of 8 interleaved pairs). Call it before the window's context exists."""
    if "LP_NUM_THREADS" not in environ:
        if cores is None:  # the cores this process may run on (a container may pin it to a few)
            cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
        environ["LP_NUM_THREADS"] = str(max(cores, 1) + 1)


class GlfwWindow:
    """A resizable window with a current OpenGL 3.3 core context.

    Input events go to the current ImGui context's IO (create it before the window).
    Raises :class:`GaitlabError` with a hint when there is no display.
    """

    def __init__(self, size: tuple[int, int], title: str = "Gaitlab", vsync: bool = True, samples: int = 0) -> None:
        if sys.platform.startswith("linux") and not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
            raise GaitlabError(NO_DISPLAY_HINT)
        software_gl_threads()
        glfw.set_error_callback(lambda code, text: None)  # errors are reported through return values
        if not glfw.init():
            raise GaitlabError(f"cannot open a window (glfw could not initialise the display "
                               f"{os.environ.get('DISPLAY', '')!r}); try 'xvfb-run gaitlab view' or 'gaitlab render'")
        glfw.window_hint(glfw.CONTEXT_VERSION_MAJOR, 3)
        glfw.window_hint(glfw.CONTEXT_VERSION_MINOR, 3)
        glfw.window_hint(glfw.OPENGL_PROFILE, glfw.OPENGL_CORE_PROFILE)
        glfw.window_hint(glfw.OPENGL_FORWARD_COMPAT, True)
        glfw.window_hint(glfw.SCALE_TO_MONITOR, True)
        glfw.window_hint(glfw.SAMPLES, samples)
        # No stencil: nothing uses one, and a software rasteriser clearing the depth of a
        # packed depth-stencil buffer must keep the stencil bits (a slower masked clear).
        glfw.window_hint(glfw.DEPTH_BITS, 24)
        glfw.window_hint(glfw.STENCIL_BITS, 0)
        self.handle = glfw.create_window(int(size[0]), int(size[1]), title, None, None)
        if not self.handle:
            glfw.terminate()
            raise GaitlabError("cannot create an OpenGL 3.3 window on this display; install Mesa's OpenGL "
                               "(apt-get install libgl1-mesa-dri) or use 'gaitlab render'")
        glfw.make_context_current(self.handle)
        glfw.swap_interval(1 if vsync else 0)
        # glFlush, looked up for this context through glfw (moderngl offers only finish):
        # hands the frame's queued drawing to the renderer's threads without waiting.
        pointer = ctypes.cast(glfw.get_proc_address("glFlush"), ctypes.c_void_p).value
        self._gl_flush = ctypes.CFUNCTYPE(None)(pointer) if pointer else None
        self._keys = _key_map()
        self._io = imgui.get_io()
        self._last_time: float | None = None
        glfw.set_key_callback(self.handle, self._on_key)
        glfw.set_char_callback(self.handle, self._on_char)
        glfw.set_cursor_pos_callback(self.handle, self._on_cursor)
        glfw.set_mouse_button_callback(self.handle, self._on_button)
        glfw.set_scroll_callback(self.handle, self._on_scroll)
        glfw.set_window_focus_callback(self.handle, self._on_focus)
        # The sizes as of the last event (asking the X server costs a round trip each).
        self._window_size: tuple[int, int] = tuple(glfw.get_window_size(self.handle))  # type: ignore[assignment]
        self._framebuffer_size: tuple[int, int] = tuple(glfw.get_framebuffer_size(self.handle))  # type: ignore[assignment]
        glfw.set_window_size_callback(self.handle, self._on_window_size)
        glfw.set_framebuffer_size_callback(self.handle, self._on_framebuffer_size)

    # -- input -> ImGui ---------------------------------------------------------------

    def _on_key(self, window, key, scancode, action, mods) -> None:
        if key == glfw.KEY_Q and action == glfw.PRESS and mods & glfw.MOD_CONTROL:
            glfw.set_window_should_close(self.handle, True)  # Ctrl+Q quits, whatever ImGui is doing
            return
        imgui_key = self._keys.get(key)
        if imgui_key is None:
            return
        down = action != glfw.RELEASE
        self._io.add_key_event(imgui_key, down)
        modifier = _MODIFIERS.get(imgui_key)
        if modifier is not None:
            self._io.add_key_event(modifier, down)

    def _on_char(self, window, char) -> None:
        if 0 < char < 0x10000:
            self._io.add_input_character(char)

    def _on_cursor(self, window, x, y) -> None:
        self._io.add_mouse_pos_event(x, y)

    def _on_button(self, window, button, action, mods) -> None:
        if 0 <= button < 5:
            self._io.add_mouse_button_event(button, action == glfw.PRESS)

    def _on_scroll(self, window, dx, dy) -> None:
        self._io.add_mouse_wheel_event(dx, dy)

    def _on_focus(self, window, focused) -> None:
        self._io.add_focus_event(bool(focused))

    def _on_window_size(self, window, width, height) -> None:
        self._window_size = (int(width), int(height))

    def _on_framebuffer_size(self, window, width, height) -> None:
        self._framebuffer_size = (int(width), int(height))

    # -- frame ------------------------------------------------------------------------

    @property
    def framebuffer_size(self) -> tuple[int, int]:
        """The framebuffer's size in pixels (as of the last event polled)."""
        return self._framebuffer_size

    @property
    def window_size(self) -> tuple[int, int]:
        """The window's size in screen coordinates (as of the last event polled)."""
        return self._window_size

    @property
    def content_scale(self) -> float:
        """The monitor's UI scale (1 on a plain display, 2 on a typical HiDPI one)."""
        sx, sy = glfw.get_window_content_scale(self.handle)
        return float(max(sx, sy, 1.0))

    def begin_frame(self, dt: float | None = None) -> float:
        """Poll events and prepare ImGui's IO; returns the frame's dt (seconds)."""
        glfw.poll_events()
        now = glfw.get_time()
        if dt is None:
            dt = (now - self._last_time) if self._last_time is not None else 1.0 / 60.0
        self._last_time = now
        win_w, win_h = self.window_size
        fb_w, fb_h = self.framebuffer_size
        self._io.display_size = imgui.ImVec2(win_w, win_h)
        # A minimised window has an empty framebuffer: keep a valid scale (ImGui needs > 0).
        scale_x = fb_w / win_w if fb_w > 0 and win_w > 0 else 1.0
        scale_y = fb_h / win_h if fb_h > 0 and win_h > 0 else 1.0
        self._io.display_framebuffer_scale = imgui.ImVec2(scale_x, scale_y)
        self._io.delta_time = max(float(dt), 1e-4)
        return float(dt)

    @property
    def should_close(self) -> bool:
        return bool(glfw.window_should_close(self.handle))

    def request_close(self) -> None:
        glfw.set_window_should_close(self.handle, True)

    def flush(self) -> None:
        """Start drawing what has been queued, without waiting for it: a software
        renderer (llvmpipe) then rasterises on its threads while Python goes on."""
        if self._gl_flush is not None:
            self._gl_flush()

    def swap(self) -> None:
        glfw.swap_buffers(self.handle)

    def close(self) -> None:
        glfw.destroy_window(self.handle)
        glfw.terminate()
