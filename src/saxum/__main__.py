"""`python -m saxum ...`: the saxum command, where the `saxum` script is not on the PATH."""

import sys

from .cli import main

sys.exit(main())
