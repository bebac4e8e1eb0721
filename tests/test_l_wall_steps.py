"""Two steps of the shaken 3D L wall that NLGS ends above the tolerance (benchmarks/convergence.py,
wall3d-shaken: 72 bricks under 0.7 g, dt 1e-3; the default hybrid's run, captured as W = H*
M^-1 H*^T (CSR H*, M^-1), q, mu in FCLIB order and NLGS's iterate r after its 5000 sweeps;
docs/method.md, "The shaken 3D L wall" (g)):
- tests/data/l_wall_step41.npz: 770 contacts, NLGS's iterate at a natural-map error of 3.1e-6
  (within _PROXIMAL_REACH = 10 times the tolerance 1e-6); Fischer-Burmeister Newton from it
  stops above the tolerance, the proximal point then reaches it.
- tests/data/l_wall_step19.npz: 770 contacts, the first onset step, NLGS's iterate at 3.9e-5;
  none of the solvers here reaches the tolerance from it in the time of a step (docs/method.md),
  while a solution exists: the problem is strictly feasible (V. Acary, F. Cadoux, C.
  Lemarechal, J. Malick, ZAMM 91(2), 2011, sec. 3).
"""

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
import scipy.sparse as sp

import saxum as sx
from saxum.solver.assembled import AssembledProblem
from saxum.solver.residual import natural_map_error

DATA = Path(__file__).resolve().parent / "data"


def _step(name: str) -> tuple[AssembledProblem, np.ndarray]:
    data = np.load(DATA / name)
    hstar = sp.csr_matrix((data["h_data"], data["h_indices"], data["h_indptr"]),
                          shape=tuple(data["h_shape"]))
    count = data["mu"].size
    local = AssembledProblem(np.arange(count), hstar, data["inv_mass"], data["q"], data["mu"])
    return local, data["r"]


_FCLIB = [1, 0, 2]
"""Saxum's contact frame (t, n, s) in FCLIB's order (n, t, s): row r of saxum's is FCLIB's
_FCLIB[r]."""


def kernel_problem(name: str) -> dict:
    """A stored step as nlgs_3d's arguments (benchmarks/anderson3d.py too): per contact the
    two bodies its rows of H* touch (candidate, antagonist), their rows in saxum's frame, W's
    diagonal blocks; v_free from q's tangential rows (H*_T v_free = q_T: H*_T has full column
    rank on the free bodies, so this is the step's v_free to round-off) and b_n = q_n - H*_n
    v_free; the impulses and velocities of NLGS's stored iterate r (v = v_free + M^-1 H*^T r)
    and the problem (AssembledProblem) that measures the natural-map error."""
    local, r = _step(name)
    hstar = local.hstar.tocsr()
    count = local.mu.size
    bodies = local.inv_mass.size // 6
    rows = hstar.toarray().reshape(count, 3, bodies, 6)
    touched = np.abs(rows).sum(axis=(1, 3)) > 0.0
    if not np.all(touched.sum(axis=1) == 2):
        raise ValueError(f"{name}: every contact must touch two bodies")
    pair = np.nonzero(touched)[1].reshape(count, 2)
    cand, ant = pair[:, 0].copy(), pair[:, 1].copy()
    at = np.arange(count)
    h_cand = rows[at, :, cand][:, _FCLIB]
    h_ant = rows[at, :, ant][:, _FCLIB]
    # W's diagonal blocks H*_a M^-1 H*_a^T, in saxum's frame
    delassus = np.einsum("arbk,bk,asbk->ars", rows, local.inv_mass.reshape(bodies, 6),
                         rows)[:, _FCLIB][:, :, _FCLIB]
    free = local.inv_mass > 0.0
    tangential = np.concatenate([3 * at + 1, 3 * at + 2])
    v_free = np.zeros(local.inv_mass.size)
    v_free[free] = np.linalg.lstsq(hstar[tangential][:, free].toarray(),
                                   local.q[tangential], rcond=None)[0]
    bias = (local.q - hstar @ v_free)[3 * at]
    inv_mass = local.inv_mass.reshape(bodies, 6)
    v = v_free + local.inv_mass * (hstar.T @ r)
    return {"cand": cand, "ant": ant, "h_cand": h_cand, "h_ant": h_ant, "delassus": delassus,
            "bias": bias, "friction": local.mu.copy(), "active": np.ones(count, dtype=bool),
            "count": count, "inv_mass": inv_mass,
            "mass": np.divide(1.0, inv_mass, out=np.zeros_like(inv_mass),
                              where=inv_mass > 0.0),
            "v_free": v_free.reshape(bodies, 6), "v": v.reshape(bodies, 6),
            "impulse": r.reshape(count, 3)[:, _FCLIB].copy(), "local": local}


def test_the_proximal_stage_finishes_a_step_fischer_burmeister_newton_leaves():
    """The hybrid's 3D attempt on step 41 (Hybrid._attempt, Newton hopeful and the proximal
    point near): Fischer-Burmeister Newton from NLGS's iterate does not reach the tolerance
    (else the attempt would end as "newton"), the proximal point does: the report says
    "proximal", and its error is the natural-map error of the impulses written, recomputed
    from W and q (to round-off: 1e-12 relative). Independently, the impulses lie in the cones,
    the modified velocities u_hat in the dual cones and r . u_hat = 0, each to the tolerance's
    size 1e-6 ||q|| (a natural-map error of 1e-6 allows that much in each)."""
    local, r0 = _step("l_wall_step41.npz")
    impulse = np.zeros((local.mu.size, 3))
    impulse[:, [1, 0, 2]] = r0.reshape(-1, 3)  # FCLIB's [n, t, s] -> saxum's (t, n, s)
    assert local.natural_map_error(impulse) > 3e-6  # measured 3.1e-6
    bodies = local.inv_mass.size // 6
    v_free, v = np.zeros((bodies, 6)), np.zeros((bodies, 6))
    hybrid = sx.Hybrid()
    report, wasted = hybrid._attempt(SimpleNamespace(model=SimpleNamespace(dim=3)), local,
                                     impulse, v_free, v, 4.7e-6, True, True)
    assert report is not None and report.solver == "proximal" and report.converged
    assert wasted == 0
    r = local.impulses(impulse)
    assert report.error <= 1e-6
    assert report.error == pytest.approx(natural_map_error(local.w, local.q, local.mu, r, 3),
                                         rel=1e-12, abs=0.0)
    size = 1e-6 * float(np.linalg.norm(local.q))
    rr, u = r.reshape(-1, 3), (local.w @ r + local.q).reshape(-1, 3)
    slip = np.linalg.norm(u[:, 1:], axis=1)
    assert np.all(local.mu * rr[:, 0] - np.linalg.norm(rr[:, 1:], axis=1) >= -size)
    assert np.all(u[:, 0] >= -size)  # u_hat_N - mu |u_T| = u_N
    u_hat = u.copy()
    u_hat[:, 0] += local.mu * slip
    assert np.abs(np.einsum("ij,ij->i", rr, u_hat)).sum() <= size * (1.0 + np.abs(rr).sum())
    # v = v_free + M^-1 H*^T r: the velocities written are those of the impulses written
    assert np.allclose(v.ravel(), local.inv_mass * (local.hstar.T @ r), rtol=0.0, atol=1e-15)


def test_the_first_onset_step_has_a_solution():
    """Step 19: NLGS's iterate is 3.9e-5 from a solution by the natural map, and a solution
    exists: the impulses stored with the step (`certificate`, found by the linear program max
    t, u_N - mu (|u_T1| + |u_T2|) >= t ||q||, t <= 1, of benchmarks/capped_steps.py
    --existence: t = 1) put u = W r + q strictly inside the dual cones K* (u_N > mu |u_T| at
    every contact, checked here on u itself), which by Acary, Cadoux, Lemarechal and Malick
    (2011, sec. 3) gives a solution whatever W's rank."""
    local, r0 = _step("l_wall_step19.npz")
    w, q, mu = local.w, local.q, local.mu
    assert natural_map_error(w, q, mu, r0, 3) == pytest.approx(3.9e-5, rel=0.01)  # measured
    u = (w @ np.load(DATA / "l_wall_step19.npz")["certificate"] + q).reshape(-1, 3)
    margin = u[:, 0] - mu * np.linalg.norm(u[:, 1:], axis=1)
    # strictly inside, by far more than round-off on u (|W| |r| 1e-16 ~ 1e-11 m/s here): the
    # LP reached its bound, a margin of ||q|| in the l1 norm of u_T
    assert margin.min() >= 0.5 * float(np.linalg.norm(q))


@pytest.mark.parametrize(("natural", "tried"), [(5e-6, True), (5e-5, False)])
def test_a_near_3d_step_is_tried_whatever_the_back_off(monkeypatch, natural, tried):
    """The first step of a small 3D L wall cut at 5 NLGS sweeps (the cap) with the back-off
    waiting (3 solves to go): where NLGS's iterate is within _PROXIMAL_REACH = 10 times the
    tolerance by the natural map (patched to 5e-6) the hybrid attempts all the same, farther
    (5e-5) it does not (the attempt patched to fail at once, so that only the decision is
    tested)."""
    from saxum.solver import assembled, hybrid
    from saxum.structures import wall3d

    monkeypatch.setattr(assembled.AssembledProblem, "natural_map_error",
                        lambda self, impulse: natural)
    calls = []
    monkeypatch.setattr(hybrid.Hybrid, "_attempt",
                        lambda self, *args: (calls.append(args[-2:]), (None, 0))[1])
    solver = sx.Hybrid(max_iterations=5, rest_after=0, refine=0.0)
    solver._wait = 3
    sim = sx.Simulation(wall3d(courses=2, length=0.5, return_length=0.5), dt=1e-3,
                        solver=solver)
    state = sim.initial_state()
    report = sim.step(state)
    assert not report.converged
    assert calls == ([(True, True)] if tried else [])


def _sweeps_3d(p: dict, accelerated: bool, tolerance: float, sweeps: int):
    """nlgs_3d's (nlgs_3d_anderson's) sweeps on kernel_problem p from its stored iterate:
    ((sweeps done, error), impulse, v)."""
    from saxum.solver.nlgs import _ANDERSON_DEPTH, nlgs_3d, nlgs_3d_anderson

    v, impulse = p["v"].copy(), p["impulse"].copy()
    args = (p["cand"], p["ant"], p["h_cand"], p["h_ant"], p["delassus"], p["bias"],
            p["friction"], p["active"], p["count"], p["inv_mass"], p["mass"], p["v_free"], v,
            np.empty_like(v), impulse, np.empty((p["count"], 38)))
    if accelerated:
        history = (np.empty((_ANDERSON_DEPTH + 2,) + v.shape),
                   np.empty((_ANDERSON_DEPTH + 2, p["count"], 3)))
        out = nlgs_3d_anderson(*args, *history, tolerance, sweeps, 1.0)
    else:
        out = nlgs_3d(*args, None, None, None, 0, tolerance, sweeps, 1.0)
    return out, impulse, v


@pytest.fixture(scope="module")
def onset19():
    return kernel_problem("l_wall_step19.npz")


def test_anderson_does_not_cure_the_first_onset_step(onset19):
    """Step 19 from NLGS's capped iterate, sweeps to NLGS's tolerance 1e-6 (docs/method.md,
    "Anderson acceleration in 3D"). The stored step is the one the run saw: NLGS's first sweep
    from its iterate changes it by 1.36e-6 (its criterion at the cap, docs/method.md (f)).
    Plain sweeps reach 1e-6 after 21 485 more (measured), far past the step's cap of 5000.
    Anderson's first mix is undone by the 3D guard (_ANDERSON_GUARD_3D: the cycle after it ends
    above the cycle before), after which it sweeps as the plain sweeps do from their 20th: it
    takes exactly one cycle more (a bound, not a cure: the mixes of the sweeps' velocities do
    not follow the slow motion of this step's impulses, 0.2 of |r| away), to the same
    natural-map error (1.6e-5, to 1e-9 relative: the same sweeps)."""
    from saxum.solver.nlgs import _ANDERSON_CYCLE

    (first, error), _, _ = _sweeps_3d(onset19, False, 0.0, 1)
    assert error == pytest.approx(1.36e-6, rel=0.01)  # measured in the run
    (plain, plain_error), r_plain, _ = _sweeps_3d(onset19, False, 1e-6, 25_000)
    (fast, fast_error), r_fast, _ = _sweeps_3d(onset19, True, 1e-6, 25_000)
    assert plain_error <= 1e-6 and fast_error <= 1e-6
    assert fast == plain + _ANDERSON_CYCLE
    local = onset19["local"]
    assert local.natural_map_error(r_fast) == pytest.approx(local.natural_map_error(r_plain),
                                                            rel=1e-9)
    assert local.natural_map_error(r_fast) > 1e-6  # still not a solution by the natural map


def test_anderson_3d_is_deterministic_and_plain_within_a_cycle(onset19):
    """Two accelerated runs of 200 sweeps (ten mixes tried) give the same bits; and a solve
    that converges within the first cycle (tolerance 2e-6: NLGS's first sweep from the stored
    iterate changes it by 1.36e-6) has no mix, so its result is that of the plain sweeps, to
    round-off of the same arithmetic (1e-15 of the impulses)."""
    (n1, e1), r1, v1 = _sweeps_3d(onset19, True, 0.0, 200)
    (n2, e2), r2, v2 = _sweeps_3d(onset19, True, 0.0, 200)
    assert (n1, e1) == (n2, e2)
    assert np.array_equal(r1, r2) and np.array_equal(v1, v2)
    (n, _), r_fast, _ = _sweeps_3d(onset19, True, 2e-6, 19)
    (m, _), r_plain, _ = _sweeps_3d(onset19, False, 2e-6, 19)
    assert n == m == 1
    assert np.allclose(r_fast, r_plain, rtol=0.0, atol=1e-15 * np.abs(r_plain).max())
