"""Command line: `saxum demo NAME`. Exit codes: 0 done, 1 failed, 2 bad input."""

import argparse
import sys
from pathlib import Path

from . import __version__
from .demos import DEMOS
from .errors import InputError

__all__ = ["main"]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="saxum", description=__doc__)
    parser.add_argument("--version", action="version", version=f"saxum {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    demo = sub.add_parser("demo", help="run a bundled demonstration")
    demo.add_argument("name", choices=sorted(DEMOS), help="which demonstration")
    demo.add_argument("-o", "--output", type=Path, default=None,
                      help="picture to write (default: saxum-demo-NAME.png here)")
    demo.add_argument("--duration", type=float, default=2.0, help="simulated time [s]")
    args = parser.parse_args(argv)
    try:
        output = args.output or Path(f"saxum-demo-{args.name}.png")
        DEMOS[args.name](output, duration=args.duration)
    except InputError as err:
        print(f"saxum: bad input: {err}", file=sys.stderr)
        return 2
    except Exception as err:  # noqa: BLE001 - report any failure as exit code 1
        print(f"saxum: failed: {err}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
