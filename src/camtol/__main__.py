"""``python -m camtol``: the command line."""

import sys

from camtol.cli.app import main

# Guarded: worker processes started with ``spawn`` (exact-mode Monte Carlo) import the
# main module again, and must not run the command a second time.
if __name__ == "__main__":
    sys.exit(main())
