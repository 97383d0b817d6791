"""`/usr/bin/python3 -m swarmform ...` (what scripts/swarm runs)."""

import sys

from . import exit_codes
from .cli import main

if __name__ == "__main__":
    try:
        sys.exit(main())
    except KeyboardInterrupt:
        sys.exit(exit_codes.INTERRUPTED)
    except BrokenPipeError:  # `swarm report ... | head`
        sys.exit(exit_codes.FAILED)
