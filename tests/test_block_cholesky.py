"""The block Cholesky factorization of the rest solution's Newton systems
(saxum.solver.block_cholesky): solutions against numpy's dense solve, the analysis kept for a
pattern and made anew for another, and the fall-back to SuperLU's LU (the rest solution found
with it: tests/validation/test_rest_solution.py)."""

import numpy as np
import pytest

from saxum.solver import block_cholesky
from saxum.solver.block_cholesky import BlockCholesky, analyse
from saxum.solver.equilibrium import _factorize, _pattern


def _system(pairs, nbodies, size, seed, shift=1.0):
    """A symmetric matrix in _pattern's layout for bodies in contact by pairs (i, j): for each
    pair, [C_i; C_j] [C_i; C_j]^T with random size x 2 columns (a contact's G P^-1/2), and
    shift x I: positive definite for shift > 0. Returns (bptr, blocks, data, indices, indptr,
    the dense matrix)."""
    rng = np.random.default_rng(seed)
    cand = np.array([i for i, _ in pairs], dtype=np.int32)
    ant = np.array([j for _, j in pairs], dtype=np.int32)
    closed = np.arange(len(pairs), dtype=np.int64)
    slot = np.arange(nbodies, dtype=np.int64)
    indptr, indices, _, _, bptr, blocks = _pattern(cand, ant, closed, slot, nbodies, size)
    dense = shift * np.eye(size * nbodies)
    for i, j in pairs:
        g = np.zeros((size * nbodies, 2))
        g[size * i: size * i + size] = rng.standard_normal((size, 2))
        g[size * j: size * j + size] = rng.standard_normal((size, 2))
        dense += g @ g.T
    columns = np.repeat(np.arange(size * nbodies), np.diff(indptr))
    return bptr, blocks, dense[indices, columns], indices, indptr, dense


def _grid(rows, columns):
    """The pairs of neighbours in a rows x columns grid of bodies (a wall's bricks)."""
    at = np.arange(rows * columns).reshape(rows, columns)
    return ([(int(a), int(b)) for a, b in zip(at[:, :-1].ravel(), at[:, 1:].ravel(), strict=True)]
            + [(int(a), int(b)) for a, b in zip(at[:-1].ravel(), at[1:].ravel(), strict=True)])


@pytest.mark.parametrize("size", [3, 6])
def test_the_factor_solves_block_systems_like_a_dense_solve(size):
    """A 6 x 8 grid of bodies (2D and 3D blocks): A^-1 b against numpy's dense solve, to
    1e-12 relative (their round-off: the condition number here is below 1e3, eps 2e-16)."""
    bptr, blocks, data, _, indptr, dense = _system(_grid(6, 8), 48, size, seed=size)
    assert np.linalg.cond(dense) < 1e3
    factor = BlockCholesky.factorize(analyse(bptr, blocks), bptr, data, indptr, size)
    b = np.random.default_rng(1).standard_normal((48, size))
    x = factor.solve(b)
    expected = np.linalg.solve(dense, b.reshape(-1)).reshape(48, size)
    assert np.abs(x - expected).max() <= 1e-12 * np.abs(expected).max()
    assert factor.solve(b.reshape(-1)).shape == (48 * size,)


def test_the_analysis_is_kept_for_its_pattern_and_made_anew_for_another(monkeypatch):
    """The same pattern (other values) takes the kept analysis; one pair more (a contact that
    closed) a new one, whose factor solves the new matrix; a kept analysis gives the factor
    bit for bit that a new one gives."""
    monkeypatch.setattr(block_cholesky, "_analyses", [])
    pairs = _grid(4, 5)
    bptr, blocks, data, _, indptr, _ = _system(pairs, 20, 3, seed=0)
    first = analyse(bptr, blocks)
    bptr2, blocks2, data2, _, indptr2, _ = _system(pairs, 20, 3, seed=1)
    assert analyse(bptr2, blocks2) is first
    kept = BlockCholesky.factorize(first, bptr2, data2, indptr2, 3)
    bptr3, blocks3, data3, _, indptr3, dense3 = _system(pairs + [(0, 19)], 20, 3, seed=2)
    other = analyse(bptr3, blocks3)
    assert other is not first
    b = np.arange(60.0)
    x = BlockCholesky.factorize(other, bptr3, data3, indptr3, 3).solve(b)
    expected = np.linalg.solve(dense3, b)
    assert np.abs(x - expected).max() <= 1e-12 * np.abs(expected).max()  # as above
    monkeypatch.setattr(block_cholesky, "_analyses", [])
    new = BlockCholesky.factorize(analyse(bptr2, blocks2), bptr2, data2, indptr2, 3)
    assert np.array_equal(new.values, kept.values)


def test_a_matrix_that_is_not_positive_definite_goes_to_superlu():
    """A symmetric indefinite matrix (a negative shift): no Cholesky factor, and the Newton
    system's factorization (equilibrium._factorize) falls back to SuperLU's LU, which solves
    it (to 1e-10 relative: the shift leaves it invertible, condition number below 1e4)."""
    bptr, blocks, data, indices, indptr, dense = _system(_grid(3, 4), 12, 3, seed=3,
                                                         shift=-0.5)
    assert np.linalg.eigvalsh(dense).min() < 0.0 and np.linalg.cond(dense) < 1e4
    assert BlockCholesky.factorize(analyse(bptr, blocks), bptr, data, indptr, 3) is None
    lu = _factorize(bptr, blocks, data, indices, indptr, 3)
    b = np.linspace(-1.0, 1.0, 36)
    expected = np.linalg.solve(dense, b)
    assert np.abs(lu.solve(b) - expected).max() <= 1e-10 * np.abs(expected).max()

