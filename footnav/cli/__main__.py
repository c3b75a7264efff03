"""``python -m footnav.cli``: the ``footnav`` command."""

import sys

from footnav.cli import main

if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
