"""The interactive viewer: glfw window, Dear ImGui (imgui-bundle) panels drawn with
moderngl, orbit camera, live plots and recording. Needs a display (or Xvfb)."""
