"""`python -m hitogata …`: the `hitogata` command."""

import sys

from hitogata.cli import main

sys.exit(main())
