"""The explorer window: a thin imgui shell over the headless LPV pipeline.

``app.App`` owns the glfw window (``explorer.gl.window``), the imgui/implot contexts and two
``Pipeline`` instances (configuration A and, for comparisons, B). Panels are functions
``gui_<panel>(state)`` over one ``state.AppState`` (``panels/``); ``layout.PANELS`` lists
them with their dock area. GL objects of the pipeline are only shown, never owned: the
textures the panels need (formulas, inspect slices, differences) live in
``textures.UiTextures``. Settings and the dock layout persist through ``persist``.
"""
