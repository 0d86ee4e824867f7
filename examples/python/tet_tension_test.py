"""The tension test on a body of tets: a bar of 4 x 1 x 1 cubes of 1 cm (24 tets) with a tet fiber along it on
every tet, whose curve is a stress in Pa (E = 1 MPa, toe to 3%, yield at 8% with hardening 0.2 MPa, rupture at
14%). One end face is fixed, the other moved at 0.1 strain per second: pulled past yield, unloaded to slack, pulled
again until it breaks. The bar's stress (the tets' mean stress, World.tet_fibers()["force"], -lambda/(h^2 V0)) against
its total strain, beside the curve pbd.Material prescribes; prints the worst gap on the loading curve and where it
broke.

Usage: tet_tension_test.py [PLOT.png]"""
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pbd

m = pbd.Material(1e6, toe_strain=0.03, yield_strain=0.08, hardening=2e5, rupture_strain=0.14)
length, rate = 0.04, 1e-4                            # m, strain per step (dt = 1 ms)
mesh = pbd.tet_box_mesh((4, 1, 1), (length, 0.01, 0.01))
far = [i for i in range(mesh.num_vertices) if mesh.positions[i, 0] > length - 1e-9]
w = pbd.WorldDouble()
body = w.add_tet_body(mesh, clamped="x_min", pinned=far, tet_fibers=pbd.Stiffness.fiber(m),
                      fiber_direction=(1.0, 0.0, 0.0))
grip = [body.first_particle + i for i in far]
p = w.params
p.dt, p.substeps, p.iterations, p.gravity = 1e-3, 10, 10, (0, 0, 0)
w.params = p

# the grip's path in total strain: up to 11% (past yield at 8%), back to 0, then up until the tets break
path = [rate * k for k in range(1, 1101)] + [rate * k for k in range(1099, -1, -1)] + \
       [rate * k for k in range(1, 2000)]
strain, stress, broke = [], [], None
for target in path:
    x = w.positions()
    x[grip, 0] = length * (1 + target)
    del x
    w.step()
    if w.last_breaks():
        broke = w.last_breaks()
        break
    strain.append(w.positions()[grip[0], 0] / length - 1)
    stress.append(w.tet_fibers()["force"].mean())     # every Kuhn tet of the bar has the same volume
strain, stress = np.array(strain), np.array(stress)
first = slice(0, 1100)                                 # the first loading, from rest
ref = np.array([m.loading_force(e) for e in strain[first]])
toe_on = strain[first] >= 0.3 * m.toe_strain           # where the stress is not ~0
gap = np.abs(stress[first] - ref)[toe_on] / ref[toe_on]
print(f"loading curve: worst gap {100 * gap.max():.2f}% of the stress from 0.3 x toe_strain on")
if broke:
    print(f"broke: {len(broke)} tet fibers at strain {broke[0].strain:.5f} (rupture_strain {m.rupture_strain}), "
          f"stress {broke[0].force / 1e3:.1f} kPa (curve {m.loading_force(broke[0].strain) / 1e3:.1f} kPa)")

curve = np.linspace(0, m.rupture_strain, 400)
plastic = m.stiffness * (0.11 - m.yield_strain) / (m.stiffness + m.hardening)
fig, ax = plt.subplots(figsize=(6.4, 4.2))
ax.plot(100 * curve, [m.loading_force(e) / 1e3 for e in curve], color="0.6", lw=4, label="prescribed curve (from rest)")
back = curve[(curve >= plastic) & (curve <= 0.11)]
ax.plot(100 * back, [m.force(e - plastic) / 1e3 for e in back], color="0.8", lw=4,
        ls="--", label=f"elastic curve after yield (plastic strain {100 * plastic:.1f}%)")
ax.plot(100 * strain, stress / 1e3, color="C0", lw=1.2, label="pbd: stress from lambda, -lambda/(h^2 V0)")
if broke:
    ax.plot([100 * broke[0].strain], [broke[0].force / 1e3], "x", color="C3", ms=9, mew=2, label="rupture")
ax.set_xlabel("total strain (%)")
ax.set_ylabel("stress along the fibers (kPa)")
ax.set_title("a bar of 24 tets with fibers: toe, linear part (E), yield, unload, reload, rupture", fontsize=10)
ax.legend(fontsize=8, loc="upper left")
fig.tight_layout()
fig.savefig(sys.argv[1] if len(sys.argv) > 1 else "tet_tension_test.png", dpi=110)
