"""Arrow keys on a focused slider or tab are that widget's, not the camera's as well.

viser's page turns the camera while an arrow key is held unless the key goes to
a text field (its `isFormElement`); a Mantine slider's thumb is a `div` with
role "slider", so a held arrow moved the slider and turned the body away at
once. The page's React handlers run on its root element, inside `<body>`, and
the camera's on `document`: a listener on `<body>` that stops an arrow key's
bubbling from a slider or a tab lets the widget have it and keeps it from the
camera. viser has no public call to run code in the page; its own
`RunJavascriptMessage` (how it sends plotly.js) does it, kept for every page that
connects later.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import viser

WIDGET_ARROWS = """
if (!window.hitogataWidgetArrows) {
  window.hitogataWidgetArrows = true;
  document.body.addEventListener("keydown", (event) => {
    const target = event.target;
    if (event.key.startsWith("Arrow") && target instanceof Element
        && target.closest('[role="slider"], [role="tab"]')) {
      event.stopPropagation();
    }
  });
}
"""


def keep_arrows_for_widgets(server: viser.ViserServer) -> None:
    """Have every page of `server` give arrow keys on a focused slider or tab to that widget alone."""
    from viser import _messages

    server._websock_server.queue_message(_messages.RunJavascriptMessage(source=WIDGET_ARROWS))
