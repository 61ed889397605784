"""The ``cvtmesh`` command, installed with the package: ``cvtmesh mesh lake -n 20000 -o lake.msh``,
or ``python -m cvtmesh ...``. The same command, words and exit codes as the Rust binary."""

from __future__ import annotations

import signal
import sys
from typing import Optional, Sequence


def main(argv: Optional[Sequence[str]] = None) -> int:
    """Run the command line ``argv`` (default ``sys.argv[1:]``) and return its exit code."""
    from ._cvtmesh import cli

    args = list(sys.argv[1:] if argv is None else argv)
    # The command runs in native code, where Python's own Ctrl-C handler would only be seen
    # once it returned; as a command it should stop at once, as the Rust binary does. An
    # interrupted command leaves no output file behind (outputs are written whole or not at all).
    if argv is None:
        signal.signal(signal.SIGINT, signal.SIG_DFL)
    sys.stdout.flush()
    sys.stderr.flush()
    return cli(["cvtmesh"] + args)


if __name__ == "__main__":
    sys.exit(main())
