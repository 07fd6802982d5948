"""``python -m simcore.cli``: the ``tofradar`` command line."""

import sys

from simcore.cli import main

sys.exit(main())
