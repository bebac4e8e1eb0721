"""Water on rigid blocks (saxum.flood) against hydrostatics and the drag formula.

- A block fully submerged in still water loses exactly the weight of the water it displaces,
  rho_w g V (Archimedes; the edge integrals of the pressure sum to it by the divergence
  theorem): checked to round-off on the load itself, on the acceleration of a block in open
  water, and on the ground's reaction under a submerged block.
- A wall retaining water on one side (tailwater at the ground, the head falling linearly
  across the wall, so the uplift on its base is the triangle of gravity-dam practice:
  rho_w g d at the heel, 0 at the toe) overturns at the depth d that statics gives,
  rho_w d^3/6 + rho_w d b^2/3 = rho_s H b^2/2 (moments about the toe of the thrust, the uplift
  and the weight), and with a small mu slides at mu (rho_s b H - rho_w d b/2) = rho_w d^2/2;
  within 1 % (the issue's tolerance), found by bisection to 0.2 %.
- Drag: a block whose upstream face is wet over a height A gets 1/2 rho_w C_d A U^2 along the
  flow (to round-off), a block shielded by another upstream gets drag only on what stands out
  above it, and a submerged block on the ground starts sliding at the velocity where the drag
  equals mu times its submerged weight, within 1 %.
"""

import math

import numpy as np
import pytest

import saxum as sx
from saxum.collapse import CollapseCriterion, critical_value
from saxum.mechanism import mechanism

G = 9.81
RHO_W = 1000.0
RHO_S = 2400.0


def _builder():
    b = sx.ModelBuilder(gravity=(0.0, -G))
    b.add_block([(-3.0, -0.3), (3.0, -0.3), (3.0, 0.0), (-3.0, 0.0)], kind=sx.BodyKind.FIXED,
                group="ground", name="ground")
    return b


def _laws(b, mu):
    b.set_law("block", "ground", sx.ContactLaw(friction=mu))
    b.set_law("block", "block", sx.ContactLaw(friction=mu))


def _reaction(state, body, dt):
    """Contact force on `body` [N/m]: sum of R_t t + R_n n over its contacts, / dt."""
    c = state.contacts
    sign = np.where(c.candidate[: c.count] == body, 1.0,
                    np.where(c.antagonist[: c.count] == body, -1.0, 0.0))
    return np.einsum("c,ci,cij->j", sign, c.impulse[: c.count], c.frame[: c.count]) / dt


def _area(poly):
    x, y = np.asarray(poly, dtype=float).T
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


STONE = [(0.1, 0.0), (0.8, 0.0), (0.95, 0.7), (0.4, 1.1), (0.0, 0.6)]  # an irregular stone


def test_submerged_block_loses_the_weight_of_displaced_water():
    b = _builder()
    stone = b.add_block(STONE, density=RHO_S, name="stone")
    _laws(b, 0.6)
    flood = sx.FloodLoad(level=3.0)
    b.add_field_load(flood)
    model = b.finalize()
    buoyancy = RHO_W * G * _area(STONE)
    for angle in (0.0, 0.3, 2.0):  # the same at any orientation, through the centroid
        q = model.body_q0.copy()
        q[stone, 2] = angle
        fx, fy, torque = flood.forces(model, q)[stone]
        assert fy == pytest.approx(buoyancy, rel=1e-13)
        assert abs(fx) < 1e-12 * buoyancy and abs(torque) < 1e-12 * buoyancy
    # resting on the ground, the ground carries the submerged weight (rho_s - rho_w) g V
    sim = sx.Simulation(model, dt=1e-3, solver=sx.NLGS(tolerance=1e-12))
    state = sim.initial_state()
    sim.run(state, 0.05)
    reaction = _reaction(state, stone, 1e-3)
    assert reaction[1] == pytest.approx((RHO_S - RHO_W) * G * _area(STONE), rel=1e-9)
    assert abs(reaction[0]) < 1e-9 * reaction[1]


def test_block_in_open_water_sinks_or_rises_at_the_reduced_gravity():
    """No ground: a block of density rho_s accelerates at g (rho_w/rho_s - 1), exactly (the
    theta-method is exact for a constant force)."""
    for density in (RHO_S, 600.0):
        b = sx.ModelBuilder(gravity=(0.0, -G))
        stone = b.add_block(STONE, density=density)
        b.set_law("block", "block", sx.ContactLaw(friction=0.6))
        b.add_field_load(sx.FloodLoad(level=50.0))
        sim = sx.Simulation(b.finalize(), dt=1e-3)
        state = sim.initial_state()
        sim.run(state, 0.1)
        expected = G * (RHO_W / density - 1.0) * state.time
        assert state.body_v[stone, 1] == pytest.approx(expected, rel=1e-12)
        assert abs(state.body_v[stone, 0]) < 1e-12 and abs(state.body_v[stone, 2]) < 1e-12


BW, HW = 0.5, 2.0  # wall width and height [m]


def _wall(mu, courses=1):
    def make(depth):
        b = _builder()
        for k in range(courses):
            y0, y1 = HW * k / courses, HW * (k + 1) / courses
            b.add_block([(0.0, y0), (BW, y0), (BW, y1), (0.0, y1)], density=RHO_S,
                        name=f"course {k + 1}")
        _laws(b, mu)
        b.add_field_load(sx.FloodLoad(level=depth, tailwater=0.0))
        return sx.Simulation(b.finalize(), dt=1e-3)
    return make


def _overturning_depth(height):
    """Root of rho_w d^3/6 + rho_w d b^2/3 = rho_s H b^2/2 (moments about the toe)."""
    roots = np.roots([RHO_W / 6.0, 0.0, RHO_W * BW**2 / 3.0, -RHO_S * height * BW**2 / 2.0])
    return float(min(r.real for r in roots if abs(r.imag) < 1e-9 and r.real > 0.0))


def _sliding_depth(mu):
    """Root of rho_w d^2/2 = mu (rho_s b H - rho_w d b/2)."""
    a, b_, c = RHO_W / 2.0, mu * RHO_W * BW / 2.0, -mu * RHO_S * BW * HW
    return (-b_ + math.sqrt(b_ * b_ - 4.0 * a * c)) / (2.0 * a)


@pytest.mark.parametrize("mu, courses, mode", [(0.8, 1, "overturns"), (0.8, 3, "overturns"),
                                               (0.3, 1, "slides")])
def test_wall_retaining_water_fails_at_the_statics_depth(mu, courses, mode):
    expected = _overturning_depth(HW) if mode == "overturns" else _sliding_depth(mu)
    # the other mode and, for the wall of courses, every joint above the base need more water
    assert min(_sliding_depth(mu), _overturning_depth(HW)) == pytest.approx(expected)
    for k in range(1, courses):
        y = HW * k / courses
        assert _overturning_depth(HW - y) + y > 1.1 * expected
    result = critical_value(_wall(mu, courses), 0.75 * expected, 1.3 * expected,
                            tolerance=0.002, criterion=CollapseCriterion(duration=1.0))
    assert result.value == pytest.approx(expected, rel=0.01)
    trial = result.collapse()
    mech = mechanism(trial.simulation.model, trial.state, trial.simulation.integrator.dt)
    if mode == "overturns":
        assert [j.bodies for j in mech.hinges] == [("ground", "course 1")]
        assert mech.hinges[0].hinge_point[0] == pytest.approx(BW)  # about the toe
    else:
        assert [j.bodies for j in mech.sliding] == [("ground", "course 1")]


def test_drag_on_the_exposed_wet_face():
    b = _builder()
    front = b.add_block([(0.0, 0.0), (0.4, 0.0), (0.4, 0.6), (0.0, 0.6)], density=RHO_S)
    behind = b.add_block([(0.5, 0.0), (0.9, 0.0), (0.9, 1.5), (0.5, 1.5)], density=RHO_S)
    slanted = b.add_block([(1.5, 0.0), (2.0, 0.0), (2.0, 0.8), (1.8, 0.8)], density=RHO_S)
    _laws(b, 0.6)
    model = b.finalize()
    level, u, cd = 1.2, 2.5, 1.3
    q = 0.5 * RHO_W * cd * u * u  # [Pa]
    still = sx.FloodLoad(level=level).forces(model)
    flow = sx.FloodLoad(level=level, velocity=u, drag_coefficient=cd).forces(model)
    drag = flow - still
    # "nothing" below is zero to round-off: the panels' ends are vertex heights
    # centre + (vertex - centre), exact only to ~1e-16 m on ~1 m, so a shielded panel may keep
    # a sliver of that width; p_d times 1e-12 m (four orders above it) is allowed
    nothing = 1e-12 * q
    # the front block's whole upstream face (0.6 m) is wet; the block behind it is exposed
    # from 0.6 m up to the water level; the slanted face (1.8, 0.8)-(1.5, 0) projects 0.8 m
    # but the block behind shields it from 0 to 1.2 m: nothing left
    assert drag[front] == pytest.approx([q * 0.6, 0.0, -q * 0.6 * 0.0], abs=1e-9 * q)
    assert drag[behind, 0] == pytest.approx(q * (level - 0.6), rel=1e-13)
    assert drag[behind, 1] == pytest.approx(0.0, abs=nothing)
    # applied at mid-height of the exposed band, 0.9 m, i.e. 0.15 m above the centre (0.75)
    assert drag[behind, 2] == pytest.approx(-q * (level - 0.6) * 0.15, rel=1e-12)
    assert drag[slanted] == pytest.approx(np.zeros(3), abs=nothing)
    # against the flow (U < 0) the slanted face is exposed downstream-first... it leads now
    back = sx.FloodLoad(level=level, velocity=-u, drag_coefficient=cd).forces(model) - still
    assert back[slanted, 0] == pytest.approx(-q * 0.8, rel=1e-13)
    assert back[behind, 0] == pytest.approx(-q * (level - 0.8), rel=1e-13)
    assert back[front] == pytest.approx(np.zeros(3), abs=nothing)


def test_submerged_block_slides_when_drag_exceeds_friction():
    """Block b x h fully submerged on the ground: drag 1/2 rho_w C_d h U^2 against
    mu (rho_s - rho_w) g b h gives U_c = sqrt(2 mu (rho_s/rho_w - 1) g b / C_d); it cannot
    overturn first since mu < b/h."""
    width, height, mu, cd = 1.0, 0.5, 0.5, 1.4

    def make(u):
        b = _builder()
        b.add_block([(0.0, 0.0), (width, 0.0), (width, height), (0.0, height)],
                    density=RHO_S, name="stone")
        _laws(b, mu)
        b.add_field_load(sx.FloodLoad(level=2.0, velocity=u, drag_coefficient=cd))
        return sx.Simulation(b.finalize(), dt=1e-3)

    expected = math.sqrt(2.0 * mu * (RHO_S / RHO_W - 1.0) * G * width / cd)
    result = critical_value(make, 0.75 * expected, 1.3 * expected, tolerance=0.002)
    assert result.value == pytest.approx(expected, rel=0.01)
    # standing just below it, the ground's friction carries the drag exactly
    sim = make(0.95 * expected)
    state = sim.initial_state()
    sim.run(state, 0.05)
    reaction = _reaction(state, 1, 1e-3)
    drag = 0.5 * RHO_W * cd * height * (0.95 * expected) ** 2
    assert -reaction[0] == pytest.approx(drag, rel=1e-6)
