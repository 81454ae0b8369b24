"""``python -m camtol``: the command line."""

import sys

from camtol.cli.app import main

sys.exit(main())
