"""OpenGL rendering with moderngl: one renderer for windows and headless EGL framebuffers.

Nothing here imports glfw or imgui; the window loop lives in :mod:`app.ui`.
"""
