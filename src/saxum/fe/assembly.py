"""Consistent mass and stiffness matrices of one block, assembled with scikit-fem
(T. Gustafsson & G.D. McBain, "scikit-fem: a Python package for finite element assembly",
JOSS 5 (2020) 2369) on linear (P1) triangles or tetrahedra.

    M = int rho N^T N dV,   K = int eps(N)^T D eps(N) dV,   C = alpha M + beta K

with D the isotropic law sigma = lambda tr(eps) I + 2 mu eps (plane stress through the
effective lambda, see material.py) and, in 2D, dV = t dA (t the thickness in plane stress,
1 m in plane strain). Degrees of freedom are ordered node by node: dof d * node + component.
"""

import scipy.sparse as sp
from skfem import (
    Basis,
    BilinearForm,
    ElementTetP1,
    ElementTriP1,
    ElementVector,
    MeshTet,
    MeshTri,
    asm,
)
from skfem.helpers import ddot, dot, sym_grad, trace

from saxum.fe.material import Elastic
from saxum.fe.mesh import Mesh

__all__ = ["damping", "mass_stiffness"]


@BilinearForm
def _mass(u, v, w):
    return w.rho * dot(u, v)


@BilinearForm
def _stiffness(u, v, w):
    eu = sym_grad(u)
    ev = sym_grad(v)
    return w.lam * trace(eu) * trace(ev) + 2.0 * w.mu * ddot(eu, ev)


def mass_stiffness(mesh: Mesh, material: Elastic) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """(M [kg], K [N/m]) as CSR matrices [d n, d n], dofs node by node; 2D matrices are for
    the block's depth (thickness in plane stress, 1 m in plane strain)."""
    dim = mesh.dim
    depth = material.depth(dim)
    if dim == 2:
        skmesh = MeshTri(mesh.nodes.T.copy(), mesh.cells.T.copy())
        element = ElementVector(ElementTriP1())
    else:
        skmesh = MeshTet(mesh.nodes.T.copy(), mesh.cells.T.copy())
        element = ElementVector(ElementTetP1())
    basis = Basis(skmesh, element)
    lam, mu = material.lame(dim)
    M = asm(_mass, basis, rho=material.density * depth)
    K = asm(_stiffness, basis, lam=lam * depth, mu=mu * depth)
    # scikit-fem's own numbering of the vector dofs, turned into ours (node by node)
    order = basis.nodal_dofs.T.ravel()
    return M[order][:, order].tocsr(), K[order][:, order].tocsr()


def damping(M: sp.csr_matrix, K: sp.csr_matrix, material: Elastic) -> sp.csr_matrix:
    """Rayleigh damping C = alpha M + beta K [N s/m]."""
    alpha, beta = material.damping
    return (alpha * M + beta * K).tocsr()
