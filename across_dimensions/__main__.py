"""``python -m across_dimensions`` is the ``across-dimensions`` command."""

import sys

from .app.cli import main

sys.exit(main())
