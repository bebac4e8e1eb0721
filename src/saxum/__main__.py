"""The saxum command: `python -m saxum ...`, and the `saxum` console script (main).

A Ctrl-C while the command's modules still load (numpy, numba, h5py...: a second or more on a
first run) exits 130 with one line, as one during the command does (saxum.cli.main), instead
of a KeyboardInterrupt traceback: `import saxum` loads nothing else (saxum/__init__.py), and
saxum.cli is imported here, inside the handler.
"""

import sys


def main() -> int:
    """Run the saxum command line on sys.argv; returns the exit code (saxum.cli)."""
    try:
        from .cli import main as cli_main
    except KeyboardInterrupt:
        print("saxum: interrupted", file=sys.stderr)
        return 130
    return cli_main()


if __name__ == "__main__":
    sys.exit(main())
