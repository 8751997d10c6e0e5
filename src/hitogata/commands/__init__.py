"""One module per `hitogata` sub-command; each has `register(subparsers)`.

A command module parses the user's words (units at the edge, once), calls the
library and prints a short summary; `cli.main` turns a `HitogataError` into one
line on stderr.
"""
