"""``python -m clearance.reports.cli``: the ``clearance`` command."""

import sys

from clearance.reports.cli.main import main

if __name__ == "__main__":
    sys.exit(main())
