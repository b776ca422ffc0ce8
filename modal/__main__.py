"""``python -m modal identify ...``: see :mod:`modal.cli`."""

import sys

from .cli import main

sys.exit(main())
