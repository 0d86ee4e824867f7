#!/usr/bin/python3
"""What one sweep per sub-step does to each Gauss-Seidel order: the figures of docs/architecture.md's section of
that name, reproduced with the Python module (build the pbd_python target; needs numpy).

  gs_orders.py plateau [N]      serial in the generator's order against the same constraints shuffled (and colored):
                                RMS stretch averaged over 1 s, final, mean speed, total energy
  gs_orders.py families [N]     which stretch family's order matters (shuffle or reverse one), 128 x 1
  gs_orders.py growth N SUBS T  growth per sub-step of the worst mode of one sub-step linearized at the hanging state
                                at time T (power iteration on finite differences of the engine's step, double)
  gs_orders.py symmetric [N]    forward against symmetric order at 1, 2 sweeps per sub-step (no bending)
  gs_orders.py linear           spectral radius of the linear model of a flat pinned grid: forward and alternating
  gs_orders.py chain            the 30-link compliant chain: error and rate per sweep against Gauss-Seidel's radius

The cloth is the study's cloth<N> (cli/study_scenes.cpp: N x N on a 1 m square, the two corners of row N-1 pinned,
PBD stretch k = 1, bending k = 0.05), built here particle by particle in the generator's order (io/src/generators.cpp
and the mesh's bending pairs) so that its stretch families can be reordered.
"""
import math
import os
import random
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.environ.get("PBD_PYTHON_DIR", os.path.join(ROOT, "build", "release", "python")))
import numpy as np  # noqa: E402
import pbd  # noqa: E402

SOLVERS = {"serial": pbd.Solver.serial, "serial-colored": pbd.Solver.serial_colored, "colored": pbd.Solver.colored}


def cloth(n, bend=0.05, shuffle="", reverse="", double=False, seed=1):
    """cloth<n>; shuffle / reverse: stretch families to reorder (h rows, v columns, d diagonals)."""
    w = pbd.WorldDouble() if double else pbd.World()
    s = 1.0 / (n - 1)
    mass = np.full(n * n, 1.0 / (n * n))
    mass[(n - 1) * n] = mass[(n - 1) * n + n - 1] = np.inf
    w.add_particles(np.array([(s * i, s * j, 1.0) for j in range(n) for i in range(n)]), mass)
    stretch = w.add_constraint_set(pbd.Stiffness.pbd_k(1.0))
    at = lambda i, j: j * n + i  # noqa: E731
    fam = {"h": [(at(i, j), at(i + 1, j)) for j in range(n) for i in range(n - 1)],
           "v": [(at(i, j), at(i, j + 1)) for j in range(n - 1) for i in range(n)],
           "d": [(at(i, j), at(i + 1, j + 1)) for j in range(n - 1) for i in range(n - 1)]}
    for f in shuffle:
        random.Random(seed).shuffle(fam[f])
    for f in reverse:
        fam[f].reverse()
    for a, b in fam["h"] + fam["v"] + fam["d"]:
        w.add_stretch(a, b, stretch)
    if bend:
        bending = w.add_constraint_set(pbd.Stiffness.pbd_k(bend))
        edges, order = {}, []
        for j in range(n - 1):
            for i in range(n - 1):
                for t in ((at(i, j), at(i + 1, j), at(i + 1, j + 1)), (at(i, j), at(i + 1, j + 1), at(i, j + 1))):
                    for k in range(3):
                        a, b, o = t[k], t[(k + 1) % 3], t[(k + 2) % 3]
                        key = (min(a, b), max(a, b))
                        if key not in edges:
                            edges[key] = []
                            order.append(key)
                        edges[key].append((a, b, o))
        for key in order:
            e = edges[key]
            if len(e) == 2:
                w.add_bending(e[0][0], e[0][1], e[0][2], e[1][2], bending)
    return w


def configure(w, substeps, iterations, solver="serial", order="forward", dt=1 / 60):
    p = w.params
    p.dt, p.substeps, p.iterations, p.solver = dt, substeps, iterations, SOLVERS[solver]
    p.sweep_order = getattr(pbd.SweepOrder, order)
    w.params = p
    return w


def run(w, steps=60):
    """RMS stretch averaged over the steps, the last one, mean speed and total energy at the end."""
    errors = []
    for _ in range(steps):
        w.step()
        errors.append(pbd.stretch_violation(w).rms)
    speed = float(np.linalg.norm(np.array(w.velocities()), axis=1).mean())
    return sum(errors) / len(errors), errors[-1], speed, pbd.energy(w).total


def line(label, w, substeps, iterations, **kw):
    avg, last, speed, energy = run(configure(w, substeps, iterations, **kw))
    print("%-44s %3d x %d  mean %7.3f%%  final %7.3f%%  mean speed %6.3f m/s  energy %8.2f J"
          % (label, substeps, iterations, 100 * avg, 100 * last, speed, energy), flush=True)


def plateau(n=100):
    for subs in (32, 64, 128):
        line("serial, generator's order", cloth(n), subs, 1)
        line("serial, stretch shuffled", cloth(n, shuffle="hvd"), subs, 1)
        line("serial-colored", cloth(n), subs, 1, solver="serial-colored")
    for subs in (32, 64):
        line("serial, generator's order", cloth(n), subs, 2)


def families(n=30):
    for label, kw in [("generator's order", {}), ("rows shuffled", {"shuffle": "h"}),
                      ("columns shuffled", {"shuffle": "v"}), ("diagonals shuffled", {"shuffle": "d"}),
                      ("rows reversed", {"reverse": "h"}), ("columns reversed", {"reverse": "v"}),
                      ("diagonals reversed", {"reverse": "d"})]:
        line("serial, " + label, cloth(n, **kw), 128, 1)


def growth(n, subs, t_state, iters=2000):
    h = (1 / 60) / subs
    ref = configure(cloth(n, shuffle="hvd", double=True), subs, 1)
    while ref.time < t_state - 1e-12:
        ref.step()
    x0, v0 = np.array(ref.positions(), copy=True), np.array(ref.velocities(), copy=True)
    free = np.repeat((np.array(ref.inverse_masses()) > 0)[:, None], 3, axis=1).ravel()
    mask = np.concatenate([free, free]).astype(float)
    m = x0.size
    for label, kw, solver in [("generator's order", {}, "serial"), ("stretch shuffled", {"shuffle": "hvd"}, "serial"),
                              ("colored", {}, "serial-colored")]:
        w = configure(cloth(n, double=True, **kw), 1, 1, solver=solver, dt=h)

        def step(x, v):
            w.time = 0.0
            w.positions()[:] = x
            w.velocities()[:] = v
            w.step()
            return np.concatenate([np.array(w.positions()).ravel(), np.array(w.velocities()).ravel()])
        f0 = step(x0, v0)
        d = np.random.default_rng(3).standard_normal(2 * m) * mask
        d /= np.linalg.norm(d)
        logs, eps = [], 1e-6
        for _ in range(iters):
            jd = (step(x0 + eps * d[:m].reshape(x0.shape), v0 + eps * d[m:].reshape(v0.shape)) - f0) / eps
            g = np.linalg.norm(jd)
            logs.append(math.log(g))
            d = jd / g
        print("%d², %d x 1, state at %.2f s, %-18s growth per sub-step %.5f"
              % (n, subs, t_state, label, math.exp(np.mean(logs[iters // 2:]))), flush=True)


def symmetric(n=30):
    for solver in ("serial", "serial-colored"):
        for subs, its in ((32, 1), (64, 1), (8, 1), (8, 2)):
            for order in ("forward", "symmetric"):
                line("%s, %s" % (solver, order), cloth(n, bend=0, double=True), subs, its, solver=solver,
                     order=order)


def linear():
    """A flat pinned n x n grid in its plane; one sweep E = prod (I - P_i) of mass-weighted projections; a sub-step
    maps (r, z = h v) to (E(r + z), E(r + z) - r)."""
    def sweep(x, w, cons):
        e = np.eye(2 * len(x))
        for a, b in cons:
            d = (x[b] - x[a]) / np.linalg.norm(x[b] - x[a])
            g = np.zeros(2 * len(x))
            g[2 * a:2 * a + 2], g[2 * b:2 * b + 2] = -d, d
            wg = np.repeat(w, 2) * g
            e -= np.outer(wg, g @ e) / (g @ wg)
        return e

    def substep(e):
        return np.block([[e, e], [e - np.eye(len(e)), e]])

    def rho(t):
        return float(np.abs(np.linalg.eigvals(t)).max())

    for n in (8, 12, 16):
        s = 1.0 / (n - 1)
        x = np.array([(s * i, s * j) for j in range(n) for i in range(n)])
        w = np.ones(n * n)
        w[(n - 1) * n] = w[(n - 1) * n + n - 1] = 0
        at = lambda i, j: j * n + i  # noqa: E731
        cons = ([(at(i, j), at(i + 1, j)) for j in range(n) for i in range(n - 1)] +
                [(at(i, j), at(i, j + 1)) for j in range(n - 1) for i in range(n)] +
                [(at(i, j), at(i + 1, j + 1)) for j in range(n - 1) for i in range(n - 1)])
        shuffled = cons[:]
        random.Random(1).shuffle(shuffled)
        color, used = [], {}  # greedy coloring in insertion order (pinned particles shared freely), color by color
        for a, b in cons:
            taken = (used.get(a, set()) if w[a] else set()) | (used.get(b, set()) if w[b] else set())
            c = next(k for k in range(len(cons)) if k not in taken)
            color.append(c)
            used.setdefault(a, set()).add(c)
            used.setdefault(b, set()).add(c)
        colored = [cons[i] for i in sorted(range(len(cons)), key=lambda i: (color[i], i))]
        for label, c in (("insertion", cons), ("shuffled", shuffled), ("colored", colored)):
            ef, eb = sweep(x, w, c), sweep(x, w, c[::-1])
            out = []
            for k in (1, 2, 3):
                f, b = np.linalg.matrix_power(ef, k), np.linalg.matrix_power(eb, k)
                out.append("%d sweeps: forward %.4f, alternating %.4f" % (
                    k, rho(substep(f)), math.sqrt(rho(substep(b) @ substep(f)))))
            print("%2d², %-9s  " % (n, label) + " | ".join(out), flush=True)


def chain():
    n, m, rest, alpha, g, h = 30, 0.01, 0.05, 1e-3, 9.81, 1 / 60
    closed = sum(alpha * (n - k + 1) * m * g for k in range(1, n + 1))
    at = alpha / h ** 2
    a = np.diag([1 / m + at] + [2 / m + at] * (n - 1)) - np.diag([1 / m] * (n - 1), 1) - np.diag([1 / m] * (n - 1), -1)
    d, lower, upper = np.diag(np.diag(a)), -np.tril(a, -1), -np.triu(a, 1)
    rho_gs = float(np.abs(np.linalg.eigvals(np.linalg.solve(d - lower, upper))).max())
    mu = float(np.abs(np.linalg.eigvals(np.linalg.solve(d, lower + upper))).max())
    print("alpha~ = %.2f; Jacobi's radius %.5f, Gauss-Seidel's %.5f (mu² %.5f), split-mass Jacobi's (1 + mu)/2 %.5f"
          % (at, mu, rho_gs, mu * mu, (1 + mu) / 2))
    for solver in ("serial", "jacobi"):
        prev = None
        for k in (25, 50, 100, 160, 200, 400):
            w = pbd.WorldDouble()
            s = w.add_constraint_set(pbd.Stiffness.xpbd_compliance(alpha))
            w.add_particle([0, 0, 0], w.kPinned)
            for i in range(1, n + 1):
                w.add_particle([0, 0, -rest * i], m)
                w.add_stretch(i - 1, i, s)
            p = w.params
            p.solver, p.damping, p.substeps, p.iterations = getattr(pbd.Solver, solver), 1.0, 1, k
            w.params = p
            for _ in range(600):
                w.step()
            e = (-float(np.array(w.positions())[n, 2]) - n * rest) / closed - 1
            rate = (e / prev[1]) ** (1 / (k - prev[0])) if prev else float("nan")
            print("%-6s %4d sweeps: error %+8.3f%%  rate per sweep since the last %.5f" % (solver, k, 100 * e, rate),
                  flush=True)
            prev = (k, e)


if __name__ == "__main__":
    cmd, args = (sys.argv[1], sys.argv[2:]) if len(sys.argv) > 1 else ("", [])
    commands = {"plateau": plateau, "families": families, "symmetric": symmetric, "linear": linear, "chain": chain,
                "growth": lambda n, s, t: growth(int(n), int(s), float(t))}
    if cmd not in commands:
        sys.exit(__doc__)
    commands[cmd](*[int(a) for a in args] if cmd not in ("growth",) else args)
