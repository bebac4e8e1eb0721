"""3 x 3 linear algebra on scalars, inlined into the compiled kernels (no arrays, no calls)."""

import numba as nb

__all__ = ["solve3"]


@nb.njit(inline="always")
def solve3(a00, a01, a02, a10, a11, a12, a20, a21, a22, b0, b1, b2):
    """x = A^-1 b by cofactors (Cramer's rule), A given by rows; A must be invertible."""
    c00 = a11 * a22 - a12 * a21
    c01 = a02 * a21 - a01 * a22
    c02 = a01 * a12 - a02 * a11
    c10 = a12 * a20 - a10 * a22
    c11 = a00 * a22 - a02 * a20
    c12 = a02 * a10 - a00 * a12
    c20 = a10 * a21 - a11 * a20
    c21 = a01 * a20 - a00 * a21
    c22 = a00 * a11 - a01 * a10
    det = a00 * c00 + a01 * c10 + a02 * c20
    return ((c00 * b0 + c01 * b1 + c02 * b2) / det, (c10 * b0 + c11 * b1 + c12 * b2) / det,
            (c20 * b0 + c21 * b1 + c22 * b2) / det)
