"""`/usr/bin/python3 -m swarmform ...` (what scripts/swarm runs)."""

import sys

from .cli import main

if __name__ == "__main__":
    try:
        sys.exit(main())
    except KeyboardInterrupt:
        sys.exit(130)
    except BrokenPipeError:  # `swarm report ... | head`
        sys.exit(1)
