#!/usr/bin/env python3
"""Three ways to time damped Hertz-Mindlin's normal dashpot in a leap-frog step,
on the dimensionless impact x'' = -x^1.5 - sqrt(5) b x^0.25 x' (docs/contact_models.md,
"What the step-time dashpot costs at rest"):

  half-step  N = N_el + c v_half                   (LAMMPS, LIGGGHTS)
  own-force  N = (N_el + c v_half) / (1 + c dt/2)  (src/contact/hertz_mindlin.hpp: the rate
             now, with the contact's own force taken as the only one on the pair)
  measured   as own-force, with the other forces on the pair added from the pair's
             acceleration measured over the last step (exact at rest: no static bias)

Prints (1) the rebound / e of one impact at n steps per contact, and (2) whether a
particle pressed between k contacts on each side (the 1D sandwich: the contacts in
parallel, as in a dense packing) settles or blows up, by beta = c dt / m* per contact.
    /usr/bin/python3 tools/hm_dashpot_schemes.py
"""
import math


def rebound_of(b):
    """The continuous impact's rebound speed (RK4), as HertzMindlin::dimensionless_restitution."""
    h, x, v = 2e-3, 0.0, 1.0

    def acc(x, v):
        if x <= 0:
            return 0.0
        return min(-x ** 1.5 - math.sqrt(5) * b * x ** 0.25 * v, 0.0)

    for _ in range(200000):
        k1x, k1v = v, acc(x, v)
        k2x, k2v = v + .5 * h * k1v, acc(x + .5 * h * k1x, v + .5 * h * k1v)
        k3x, k3v = v + .5 * h * k2v, acc(x + .5 * h * k2x, v + .5 * h * k2v)
        k4x, k4v = v + h * k3v, acc(x + h * k3x, v + h * k3v)
        xn = x + h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x)
        vn = v + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)
        if xn <= 0:
            return -vn if vn < 0 else 0.0
        x, v = xn, vn
    return 0.0


def damping_for(e):
    lo, hi = 0.0, 1.0
    while rebound_of(hi) > e and hi < 1e3:
        hi *= 2
    for _ in range(50):
        mid = .5 * (lo + hi)
        lo, hi = (mid, hi) if rebound_of(mid) > e else (lo, mid)
    return .5 * (lo + hi)


def normal_force(scheme, n_el, c, v, dt, other):
    if scheme == "half-step":
        return n_el + c * v
    if scheme == "own-force":
        return (n_el + c * v) / (1 + 0.5 * c * dt)
    return (n_el + c * (v + 0.5 * other)) / (1 + 0.5 * c * dt)


def impact(b, n, scheme):
    """Rebound / approach speed of the leap-frog impact, n steps per contact time (3.2)."""
    dt, x, v, u = 3.2 / n, 0.0, 1.0, None
    x += dt * v
    for _ in range(10 ** 6):
        if x <= 0:
            return -v
        c = math.sqrt(5) * b * x ** 0.25
        other = 0.0 if u is None else v - u
        f = max(normal_force(scheme, x ** 1.5, c, v, dt, other), 0.0)
        u = v - dt * f
        v -= dt * f
        x += dt * v
    return float("nan")


def sandwich(scheme, beta, stiffness, per_side, steps=6000):
    """Largest |x| over the last steps of a particle (m = 1, dt = 1) between per_side linear
    contacts on each side (k dt^2 / m = stiffness, c dt / m = beta), started 0.01 off centre."""
    x, v, u = 0.01, 0.0, {}
    for _ in range(steps):
        force = 0.0
        for q in range(2 * per_side):
            side = -1 if q % 2 == 0 else 1
            vn = side * v
            other = 0.0 if q not in u else vn - u[q]
            f = max(normal_force(scheme, stiffness * (1 + side * x), beta, vn, 1.0, other), 0.0)
            u[q] = vn - f
            force -= side * f
        v += force
        x += v
        if not math.isfinite(x) or abs(x) > 1e6:
            return "blows up"
    return "settles" if abs(x) < 1e-3 else f"|x| {abs(x):.2g}"


schemes = ("half-step", "own-force", "measured")
print("(1) rebound / e of one impact, by steps per contact n")
print(f"{'e':>5} {'n':>4}  " + "  ".join(f"{s:>10}" for s in schemes))
for e in (0.02, 0.1, 0.5):
    b = damping_for(e)
    for n in (5, 10, 40, 160):
        print(f"{e:5.2f} {n:4d}  " + "  ".join(f"{impact(b, n, s) / e:10.3f}" for s in schemes))
print("\n(2) a particle between k contacts on each side, k dt^2/m = 0.01")
print(f"{'k':>3} {'beta':>5}  " + "  ".join(f"{s:>10}" for s in schemes))
for per_side in (1, 3, 6):
    for beta in (0.1, 0.3, 0.5, 1.0, 2.0, 5.0):
        print(f"{per_side:3d} {beta:5.1f}  " + "  ".join(f"{sandwich(s, beta, 0.01, per_side):>10}" for s in schemes))
