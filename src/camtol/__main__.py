"""``python -m camtol``: the command line."""

import sys

from camtol.cli import main

sys.exit(main())
