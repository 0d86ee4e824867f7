"""A fiber's tension test: four fibers of 1 cm in a row between a fixed grip and one moved at 0.1 strain per second
(quasi-static against the chain's period of about 1 ms), pulled past yield, unloaded to slack, pulled again until it
breaks. The tension read from lambda (World.fibers()["force"], -lambda/h^2) against the total strain, beside the
curve pbd.Material prescribes; prints the worst gap on the loading curve and where it broke.

Usage: tension_test.py [PLOT.png]"""
import math
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pbd

m = pbd.Material(1000.0, toe_strain=0.03, yield_strain=0.08, hardening=200.0, rupture_strain=0.14)
n, rest, rate = 4, 0.01, 1e-4                        # fibers, m each, strain per step (dt = 1 ms)
w = pbd.WorldDouble()
for i in range(n + 1):
    w.add_particle((rest * i, 0, 0), math.inf if i in (0, n) else 1e-3)
s = w.add_constraint_set(pbd.Stiffness.fiber(m))
for i in range(n):
    w.add_fiber(i, i + 1, s)
p = w.params
p.dt, p.substeps, p.iterations, p.gravity = 1e-3, 10, 10, (0, 0, 0)
w.params = p

# the grip's path in total strain: up to 11% (past yield at 8%), back to 0, then up until the fibers break
path = [rate * k for k in range(1, 1101)] + [rate * k for k in range(1099, -1, -1)] + \
       [rate * k for k in range(1, 2000)]
strain, force, broke = [], [], None
for target in path:
    w.positions()[n, 0] = rest * n * (1 + target)
    w.step()
    if w.last_breaks():
        broke = w.last_breaks()[0]
        break
    strain.append(w.positions()[n, 0] / (rest * n) - 1)
    force.append(w.fibers()["force"][-1])
strain, force = np.array(strain), np.array(force)
first = slice(0, 1100)                                 # the first loading, from rest
gap = np.abs(force[first] - [m.loading_force(e) for e in strain[first]])
ref = np.maximum(np.array([m.loading_force(e) for e in strain[first]]), 1e-12)
toe_on = strain[first] >= 0.3 * m.toe_strain           # where the force is not ~0
print(f"loading curve: worst gap {100 * (gap[toe_on] / ref[toe_on]).max():.2f}% of the force from 0.3 x toe_strain on")
if broke:
    print(f"broke at strain {broke.strain:.5f} (rupture_strain {m.rupture_strain}), force {broke.force:.2f} N "
          f"(curve {m.loading_force(broke.strain):.2f} N)")

curve = np.linspace(0, m.rupture_strain, 400)
plastic = m.stiffness * (0.11 - m.yield_strain) / (m.stiffness + m.hardening)
fig, ax = plt.subplots(figsize=(6.4, 4.2))
ax.plot(100 * curve, [m.loading_force(e) for e in curve], color="0.6", lw=4, label="prescribed curve (from rest)")
back = curve[(curve >= plastic) & (curve <= 0.11)]
ax.plot(100 * back, [m.force(e - plastic) for e in back], color="0.8", lw=4,
        ls="--", label=f"elastic curve after yield (plastic strain {100 * plastic:.1f}%)")
ax.plot(100 * strain, force, color="C0", lw=1.2, label="pbd: tension from lambda, -lambda/h^2")
if broke:
    ax.plot([100 * broke.strain], [broke.force], "x", color="C3", ms=9, mew=2, label="rupture")
ax.set_xlabel("total strain (%)")
ax.set_ylabel("tension (N)")
ax.set_title("fiber tension test: toe, linear part, yield, unload, reload, rupture", fontsize=10)
ax.legend(fontsize=8, loc="upper left")
fig.tight_layout()
fig.savefig(sys.argv[1] if len(sys.argv) > 1 else "tension_test.png", dpi=110)
