"""The one exception type a user's mistake raises.

Every message is a single line that names the file or the entry, the value
given and what is allowed, so the CLI can print it as-is instead of a traceback.
"""


class HitogataError(ValueError):
    """A user-facing error with a one-line message."""
