"""Elastic material of deformable blocks: Lame parameters and bad input."""

import math

import pytest

from saxum.errors import InputError
from saxum.fe import Elastic


def test_plane_stress_lambda_is_the_effective_one():
    # Zienkiewicz & Taylor vol. 1 sec. 6.2: plane stress sigma = E/(1-nu^2) [[1, nu], [nu, 1]]
    # eps on the normal part, i.e. lambda* + 2 mu = E / (1 - nu^2) and lambda* = E nu / (1-nu^2)
    E, nu = 3.0e10, 0.25
    lam, mu = Elastic(E, nu, 2500.0, thickness=0.2).lame(2)
    assert math.isclose(lam, E * nu / (1 - nu * nu), rel_tol=1e-14)
    assert math.isclose(lam + 2 * mu, E / (1 - nu * nu), rel_tol=1e-14)
    lam3, mu3 = Elastic(E, nu, 2500.0).lame(2)
    assert math.isclose(lam3, E * nu / ((1 + nu) * (1 - 2 * nu)), rel_tol=1e-14)
    assert math.isclose(mu3, E / (2 * (1 + nu)), rel_tol=1e-14)


def test_row_and_depth():
    stress = Elastic(1e9, 0.2, 2000.0, damping=(0.5, 1e-4), thickness=0.3)
    assert stress.row().tolist() == [1e9, 0.2, 2000.0, 0.5, 1e-4, 0.3]
    # depth is the given thickness or 1 m of plane strain, returned, not computed: 1e-15 is
    # round-off room only
    assert math.isclose(stress.depth(2), 0.3, rel_tol=1e-15)
    assert math.isclose(Elastic(1e9, 0.2, 2000.0).depth(2), 1.0, rel_tol=1e-15)
    with pytest.raises(InputError, match="thickness.*2D plane stress only"):
        stress.depth(3)


@pytest.mark.parametrize("kwargs, message", [
    (dict(E=0.0), "Young's modulus E = 0.0 Pa must be positive"),
    (dict(E=-1e9), "Young's modulus E = -1000000000.0 Pa must be positive"),
    (dict(E="stone"), "E = 'stone' is not a number"),
    (dict(E=math.inf), "E = inf is not finite"),
    (dict(nu=0.5), r"Poisson's ratio nu = 0.5 must lie in \(-1, 0.5\)"),
    (dict(nu=-1.0), r"Poisson's ratio nu = -1.0 must lie in \(-1, 0.5\)"),
    (dict(density=0.0), "density = 0.0 kg/m\\^3 must be positive"),
    (dict(damping=(-0.1, 0.0)), "negative"),
    (dict(damping=(0.0, -1e-3)), "negative"),
    (dict(damping=0.1), "must be a pair"),
    (dict(thickness=0.0), "thickness = 0.0 m must be positive"),
])
def test_bad_material_is_refused_with_the_parameter_named(kwargs, message):
    args = dict(E=1e9, nu=0.2, density=2000.0) | kwargs
    with pytest.raises(InputError, match=message):
        Elastic(**args)
