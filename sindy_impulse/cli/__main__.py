"""``python -m sindy_impulse.cli``: the ``sindy-impulse`` command."""

import sys

from . import main

sys.exit(main())
