"""One module per panel; each exposes ``gui_<panel>(state: AppState)``."""
