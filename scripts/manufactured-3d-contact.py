#!/usr/bin/env python3
"""Symbolic check of M1-3D (docs/manufactured.md, section 11): the displacements typed in
directly (not through the recipe of the code), then equilibrium-free identities checked exactly
and the reference values of the tests printed. Run: python3 scripts/manufactured-3d-contact.py
(needs sympy)."""
import sympy as sp

x, y, z = sp.symbols("x y z", real=True)
lam, mu = sp.Rational(2), sp.Rational(1)
kappa = 1 / (lam + 2 * mu)
S = (7 - 3 * sp.sqrt(5)) / 2  # r_c^2, r_c = (3 - sqrt 5)/2
s = (x - sp.Rational(1, 2)) ** 2 + (y - sp.Rational(1, 2)) ** 2
p0, q0 = 1, sp.Rational(1, 20)
w = (1 + x**2 + y**2) / 20
h0 = (2 + x + y + x**2 + y**2) / 40


def fields(region):
    """The displacements of both bodies where the pressure (region 'in') or the opening
    (region 'out') is the non-zero power."""
    p = p0 * (1 - s / S) ** 4 if region == "in" else sp.Integer(0)
    q = q0 * ((s - S) / (sp.Rational(1, 2) - S)) ** 5 if region == "out" else sp.Integer(0)
    phi1 = -w - h0 + q
    u1 = sp.Matrix([
        (1 - z**2) * x**2 / 20 - z * (1 - z) * sp.diff(phi1, x),
        (1 - z**2) * x * y / 20 - z * (1 - z) * sp.diff(phi1, y),
        (1 - z**2) * phi1 - kappa * z * (1 - z) * (p + lam * (x / 10 + x / 20)),
    ])
    u2 = sp.Matrix([
        -(1 - z**2) * x / 20 + z * (1 + z) * sp.diff(w, x),
        -(1 - z**2) * y / 40 + z * (1 + z) * sp.diff(w, y),
        -(1 - z**2) * w - kappa * z * (1 + z) * (p + lam * (-sp.Rational(1, 20) - sp.Rational(1, 40))),
    ])
    return u1, u2, p, q


X = [x, y, z]


def grad(u):
    return sp.Matrix(3, 3, lambda i, j: sp.diff(u[i], X[j]))


def stress(u):
    g = grad(u)
    eps = (g + g.T) / 2
    return lam * eps.trace() * sp.eye(3) + 2 * mu * eps


def force(u):
    sig = stress(u)
    return sp.Matrix([-sum(sp.diff(sig[i, j], X[j]) for j in range(3)) for i in range(3)])


for region in ["in", "out"]:
    u1, u2, p, q = fields(region)
    assert sp.simplify(u1.subs(z, 1)) == sp.zeros(3, 1)
    assert sp.simplify(u2.subs(z, -1)) == sp.zeros(3, 1)
    for u in (u1, u2):
        sig = stress(u).subs(z, 0)
        assert sp.simplify(sig[0, 2]) == 0 and sp.simplify(sig[1, 2]) == 0
        assert sp.simplify(sig[2, 2] + p) == 0
    jump = u2[2].subs(z, 0) - u1[2].subs(z, 0)
    assert sp.simplify(h0 - jump - q) == 0
print("identities hold: u = 0 on the clamped sides, no shear, sigma_zz = -p, gap = q")

# C^k across the circle: the powers 4 and 5 of (S - s) and (s - S).
resultant = sp.integrate(p0 * (1 - sp.Symbol("t") / S) ** 4 * sp.pi, (sp.Symbol("t"), 0, S))
print("int p dA =", sp.nsimplify(resultant), "=", sp.N(resultant, 17))

fmt = lambda v: " ".join(f"{float(sp.N(c, 30)):.17g}" for c in v)
for label, point, region in [
    ("body1", (sp.Rational(2, 5), sp.Rational(11, 20), sp.Rational(1, 3)), "in"),
    ("body1", (sp.Rational(9, 10), sp.Rational(1, 5), sp.Rational(3, 4)), "out"),
    ("body2", (sp.Rational(2, 5), sp.Rational(11, 20), -sp.Rational(1, 3)), "in"),
    ("body2", (sp.Rational(9, 10), sp.Rational(1, 5), -sp.Rational(3, 4)), "out"),
]:
    u1, u2, p, q = fields(region)
    u = u1 if label == "body1" else u2
    at = dict(zip(X, point))
    sig = stress(u).subs(at)
    print(f"{label} {tuple(str(c) for c in point)} u:", fmt(u.subs(at)))
    print(f"  sigma xx yy zz yz xz xy:", fmt([sig[0, 0], sig[1, 1], sig[2, 2], sig[1, 2], sig[0, 2], sig[0, 1]]))
    print(f"  f:", fmt(force(u).subs(at)))
for point, region in [((sp.Rational(2, 5), sp.Rational(11, 20)), "in"), ((sp.Rational(9, 10), sp.Rational(1, 5)), "out")]:
    u1, u2, p, q = fields(region)
    at = {x: point[0], y: point[1], z: 0}
    print(f"Gamma_C {point}: sigma_nu [u]_nu h0 gap:", fmt([-p.subs(at), (u2[2] - u1[2]).subs(at), h0.subs(at), q.subs(at)]))
