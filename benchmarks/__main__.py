"""``python -m benchmarks NAME [args]``: run a registered benchmark (no NAME: list them)."""

import sys

from . import REGISTRY, load


def main(argv: list[str]) -> int:
    """Run ``NAME`` with the remaining arguments, or list the benchmarks."""
    if not argv or argv[0] in ("-h", "--help", "list"):
        width = max(map(len, REGISTRY))
        print("python -m benchmarks NAME [args]   (NAME --help: its options)\n")
        for name, what in REGISTRY.items():
            print(f"  {name:<{width}}  {what}")
        return 0
    return load(argv[0]).main(argv[1:]) or 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
