"""The interactive web viewer (`hitogata view`): pose a body by its muscles in a browser.

`serve(body, host, port)` starts it and returns the running `ViewerApp`.
Needs viser (imported when a viewer starts, so the rest of hitogata runs without it).
"""

from hitogata.viewer.app import ViewerApp, serve

__all__ = ["ViewerApp", "serve"]
