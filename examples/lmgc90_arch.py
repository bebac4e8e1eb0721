"""LMGC90's example RIGID_2D/arche_plein_ceintre_2D in saxum: its numbers, saxum's code.

The example (its gen_sample.py and command.py): a semicircular arch of 11 voussoirs between
radii 0.8 and 1.0 m, STONE of density 1500 kg/m^3, each voussoir's joint with the next open
by an angle of pi/100 (3.1 cm at the extrados, 2.5 cm at the intrados), on a fixed JONCx
foundation (centre (0, -0.05), ax1 = 1.1, ax2 = 0.05 m: here a capsule 2.2 m long, radius
0.05 m, its top at y = 0). Laws: IQS_CLB_g0, mu = 0.5, between voussoirs and IQS_CLB,
mu = 0.5, with the foundation, alert pi/100 m for both. Run: 100 steps of dt = 1e-3 s,
theta = 0.5, NLGS 'Quad ' 1e-4, relaxation 1, at most 50 x 10 sweeps.

The _g0 law (saxum.laws, ContactLaw.initial_gap) subtracts each joint's gap at the first
step, so the open joints act as closed and the arch stands as in LMGC90: the crown goes down
0.1 um in the 100 steps. `main` runs it, and for comparison the same arch with IQS_CLB
between voussoirs (no _g0): its crown falls freely (g t^2 / 2 = 49 mm in 0.1 s: its faces
are near vertical, the fall closes its joints by a seventh of it). It returns the crown's
drop in each [m] and prints the verdicts.

    PYTHONPATH=src python examples/lmgc90_arch.py
"""

import math

import saxum as sx

VOUSSOIRS = 11
R_IN, R_OUT = 0.8, 1.0  # [m]
JOINT = math.pi / 100.0  # [rad] the angle each joint is open by
DENSITY = 1500.0  # [kg/m^3]
FRICTION = 0.5
STANDS = 0.01
"""[m] The verdict: the arch stands if its crown went down by less than 1 cm."""


def arch(joint: float = JOINT, *, g0: bool = True) -> sx.Model:
    """The example's arch with joints open by `joint` [rad] (0: closed), the joints' law
    IQS_CLB_g0 (g0 False: IQS_CLB)."""
    b = sx.ModelBuilder()
    e = R_OUT - R_IN
    b.add_capsule((0.0, -0.25 * e), 2.0 * (R_OUT + 0.5 * e), 0.25 * e, kind=sx.BodyKind.FIXED,
                  group="foundation", name="foundation")
    opening = (math.pi - (VOUSSOIRS - 1) * joint) / VOUSSOIRS
    for i in range(VOUSSOIRS):
        a0 = i * (opening + joint)
        a1 = a0 + opening
        b.add_block([(R_IN * math.cos(a0), R_IN * math.sin(a0)),
                     (R_OUT * math.cos(a0), R_OUT * math.sin(a0)),
                     (R_OUT * math.cos(a1), R_OUT * math.sin(a1)),
                     (R_IN * math.cos(a1), R_IN * math.sin(a1))],
                    density=DENSITY, group="voussoir", name=f"voussoir {i + 1}")
    iqs = sx.LawKind.SIGNORINI_COULOMB
    b.set_law("voussoir", "voussoir", sx.ContactLaw(friction=FRICTION, kind=iqs,
                                                    alert=R_OUT * JOINT, initial_gap=g0))
    b.set_law("voussoir", "foundation", sx.ContactLaw(friction=FRICTION, kind=iqs,
                                                      alert=R_OUT * JOINT))
    return b.finalize()


def crown_drop(model: sx.Model, duration: float) -> float:
    """How far the crown voussoir went down [m] in `duration` [s] (LMGC90's settings)."""
    sim = sx.Simulation(model, dt=1e-3, theta=0.5,
                        solver=sx.NLGS(tolerance=1e-4, criterion="quad", max_iterations=500))
    state = sim.initial_state()
    sim.run(state, duration)
    crown = model.body(f"voussoir {VOUSSOIRS // 2 + 1}")
    return float(model.body_q0[crown, 1] - state.body_q[crown, 1])


def main(duration: float = 0.1) -> dict[str, float]:
    drops = {"IQS_CLB_g0 (LMGC90's example)": crown_drop(arch(), duration),
             "IQS_CLB (no _g0)": crown_drop(arch(g0=False), duration)}
    for name, drop in drops.items():
        verdict = "stands" if drop < STANDS else "falls"
        print(f"{name}: the crown went down {1e3 * drop:.3g} mm in {duration:g} s: {verdict}")
    return drops


if __name__ == "__main__":
    main()
