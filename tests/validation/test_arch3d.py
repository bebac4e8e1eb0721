"""The extruded semicircular arch: the 3D model of the 2D validation arch, given a depth.

An arch of voussoirs that are prisms through the depth, on a support that is a prism too,
under gravity and a horizontal load in its plane, is a plane problem: every section of the
3D model carries the same load as the 2D model (per metre of depth), so the 3D model must
stand and collapse where the 2D one does (tests/validation/test_arch.py: t/R = 0.15 stands,
t/R = 0.09 collapses, after Heyman 1969 and the minimum t/R = 0.1075 of Milankovitch /
Cocchetti et al., Appl. Mech. Rev. 64, 2011) and have the same horizontal collapse load factor
(tests/validation/test_arch_horizontal.py: within 3 % of a four-hinge limit analysis).

Model: saxum.structures.extruded(semicircular_arch(R = 1 m, 15 voussoirs, 2000 kg/m^3)),
depth 0.5 m, one block per voussoir through the depth; dt = 1e-3 s, default NLGS.
- t/R = 0.15 stands: no voussoir moves by more than 1e-4 R in 2 s;
- t/R = 0.09 collapses: the crown falls by more than 0.1 R within 2 s;
- horizontal load factor (mu = 1, saxum.collapse.critical_value to 0.5 %, the load along x
  in 3D): within 2 % of the 2D model's (issue 6), bisected the same way; and the same
  mechanism: 0.05 s into the collapse, hinges at the same four joints, on the same sides
  (intrados or extrados), as the 2D arch's (tests/validation/test_arch_horizontal.py checks
  those against a limit analysis), each 3D hinge a line through the depth.
"""

import dataclasses
import math

import numpy as np
import pytest
from limit_analysis import joint_index

import saxum as sx
from saxum.collapse import CollapseCriterion, critical_value
from saxum.mechanism import mechanism
from saxum.structures import extruded, semicircular_arch

RADIUS, VOUSSOIRS, DEPTH, DT = 1.0, 15, 0.5, 1e-3


def _arch(ratio, friction=0.6):
    return semicircular_arch(radius=RADIUS, thickness=ratio * RADIUS, voussoirs=VOUSSOIRS,
                             density=2000.0, friction=friction)


def _crown_history(ratio, duration=2.0):
    model = extruded(_arch(ratio), DEPTH)
    assert model.dim == 3 and model.body_count == VOUSSOIRS + 1
    crown = model.body(f"voussoir {VOUSSOIRS // 2 + 1}")
    sim = sx.Simulation(model, dt=DT)
    state = sim.initial_state()
    drop = []
    for _ in range(round(duration / DT)):
        sim.step(state)
        drop.append(model.body_q0[crown, 2] - state.body_q[crown, 2])
    return model, sim, state, np.array(drop)


def test_extruded_thick_arch_stands():
    model, sim, state, _ = _crown_history(0.15)
    moved = np.linalg.norm(state.body_q[:, :3] - model.body_q0[:, :3], axis=1)
    assert moved.max() < 1e-4 * RADIUS
    assert np.all(sim.log.converged)


def test_extruded_thin_arch_collapses():
    _, sim, _, drop = _crown_history(0.09)
    assert drop.max() > 0.1 * RADIUS
    assert drop.min() > -1e-3 * RADIUS
    assert np.all(np.isfinite(sim.log.kinetic_energy))


def _loaded(model, factor):
    g = float(np.linalg.norm(model.gravity))
    load = (factor * g, 0.0) if model.dim == 2 else (factor * g, 0.0, 0.0)
    return sx.Simulation(dataclasses.replace(model, accelerations=(lambda t: load,)), dt=DT)


def test_horizontal_collapse_load_factor_matches_the_2d_arch():
    plane = _arch(0.15, friction=1.0)
    solid = extruded(plane, DEPTH)
    criterion = CollapseCriterion(duration=1.0)
    results = [critical_value(lambda f, m=m: _loaded(m, f), 0.075, 0.225, tolerance=0.005,
                              criterion=criterion) for m in (plane, solid)]
    lam_2d, lam_3d = (r.value for r in results)
    assert 0.1 < lam_2d < 0.2
    assert lam_3d == pytest.approx(lam_2d, rel=0.02)
    hinges = []
    for result in results:
        trial = result.collapse()
        trial.simulation.run(trial.state, 0.05)  # every hinge visibly open
        mech = mechanism(trial.simulation.model, trial.state, trial.simulation.integrator.dt)
        assert not mech.sliding
        hinges.append(sorted(
            (joint_index(j, VOUSSOIRS),
             "intrados" if math.hypot(j.hinge_point[0], j.hinge_point[-1]) < RADIUS
             else "extrados") for j in mech.hinges))
        if mech.hinges[0].hinge_line is not None:  # 3D: lines through the whole depth
            for j in mech.hinges:
                (_, y0, _), (_, y1, _) = j.hinge_line
                assert abs(y1 - y0) == pytest.approx(DEPTH, rel=1e-6)
    assert len(hinges[0]) == 4 and hinges[1] == hinges[0]
