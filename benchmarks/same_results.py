"""Whether two saxum results files hold the same numbers, bit for bit: every dataset and every
attribute, compared by their bytes (variable-length strings by their values). For checks that
a change leaves results unchanged on one machine (BENCHMARKS.md), e.g. the first run with and
without the kernels shipped in the package:

    python benchmarks/same_results.py A.h5 B.h5 [A2.h5 B2.h5 ...]

Prints, for each pair, how many datasets and attributes are identical and which differ; exits
1 if any differ.
"""

import sys

import h5py
import numpy as np


def _contents(path: str) -> dict[str, bytes]:
    """{dataset name or "name@attribute": its bytes}."""
    out = {}

    def as_bytes(value) -> bytes:
        value = np.asarray(value)
        return repr(value.tolist()).encode() if value.dtype == object else value.tobytes()

    def visit(name: str, item) -> None:
        if isinstance(item, h5py.Dataset):
            out[name] = as_bytes(item[()])
        for key, value in item.attrs.items():
            out[f"{name}@{key}"] = as_bytes(value)

    with h5py.File(path, "r") as f:
        visit("", f)
        f.visititems(visit)
    return out


def main() -> int:
    paths = sys.argv[1:]
    if not paths or len(paths) % 2:
        print(__doc__)
        return 2
    same = True
    for a, b in zip(paths[::2], paths[1::2], strict=True):
        first, second = _contents(a), _contents(b)
        differ = sorted(k for k in first.keys() & second.keys() if first[k] != second[k])
        alone = sorted(first.keys() ^ second.keys())
        same = same and not differ and not alone
        print(f"{a} / {b}: {len(first.keys() & second.keys()) - len(differ)} of "
              f"{len(first.keys() | second.keys())} identical; differ: {differ or 'none'}; "
              f"in one file only: {alone or 'none'}")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
