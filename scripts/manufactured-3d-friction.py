#!/usr/bin/env python3
"""Symbolic check of M2-3D (docs/manufactured.md, section 11): Tresca friction between two
stacked boxes in full contact, sticking inside the disc r < r_s and slipping outside it. The
displacements are typed in directly (not through the recipe of the code); the script checks
exactly, in the stick disc and in the slip region, that u = 0 on the clamped sides, that both
bodies carry the shear traction t and the pressure p on z = 0, that the bodies touch
([u]_nu = h0), the Tresca conditions (|t| < g_F and no slip inside; |t| = g_F and a slip
-c sigma_1tau with c >= 0 outside), the continuity of the switch functions across the circle,
and prints the reference values of the tests. Run: python3 scripts/manufactured-3d-friction.py
(needs sympy)."""
import sympy as sp

x, y, z = sp.symbols("x y z", real=True)
lam, mu = sp.Rational(2), sp.Rational(1)
kappa = 1 / (lam + 2 * mu)
S = (sp.sqrt(2) - 1) / 2  # r_s^2
s = (x - sp.Rational(1, 2)) ** 2 + (y - sp.Rational(1, 2)) ** 2
g0, s0, p0 = sp.Rational(1, 4), sp.Rational(1, 20), 1
m = sp.Matrix([g0 * (1 + x / 2), g0 * (y - sp.Rational(1, 2))])
gF = sp.sqrt(m.dot(m))
p = p0 * (1 + (x + y) / 2 - (x**2 + y**2) / 2)
w = (1 + x**2 + y**2) / 20
h0 = (2 + x + y + x**2 + y**2) / 40
RHO_IN = (1 - s / S) ** 4
SL_OUT = s0 * ((s - S) / (sp.Rational(1, 2) - S)) ** 3


def fields(region):
    """The displacements of both bodies in the stick disc ('in') or the slip region ('out')."""
    rho = RHO_IN if region == "in" else sp.Integer(0)
    sl = SL_OUT if region == "out" else sp.Integer(0)
    t = (1 - rho) * m
    a1 = sl * m / (2 * g0)
    a2 = -a1
    phi1, phi2 = -w - h0, -w
    div1 = sp.diff(a1[0], x) + sp.diff(a1[1], y)
    div2 = -div1
    u1 = sp.Matrix([
        (1 - z**2) * a1[0] + z * (1 - z) * (t[0] / mu - sp.diff(phi1, x)),
        (1 - z**2) * a1[1] + z * (1 - z) * (t[1] / mu - sp.diff(phi1, y)),
        (1 - z**2) * phi1 - kappa * z * (1 - z) * (p + lam * div1),
    ])
    u2 = sp.Matrix([
        (1 - z**2) * a2[0] + z * (1 + z) * (t[0] / mu - sp.diff(phi2, x)),
        (1 - z**2) * a2[1] + z * (1 + z) * (t[1] / mu - sp.diff(phi2, y)),
        (1 - z**2) * phi2 - kappa * z * (1 + z) * (p + lam * div2),
    ])
    return u1, u2, t, rho, sl


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
    u1, u2, t, rho, sl = fields(region)
    assert sp.simplify(u1.subs(z, 1)) == sp.zeros(3, 1)
    assert sp.simplify(u2.subs(z, -1)) == sp.zeros(3, 1)
    for u in (u1, u2):
        sig = stress(u).subs(z, 0)
        assert sp.simplify(sig[0, 2] - t[0]) == 0 and sp.simplify(sig[1, 2] - t[1]) == 0
        assert sp.simplify(sig[2, 2] + p) == 0
    jump_n = u2[2].subs(z, 0) - u1[2].subs(z, 0)
    assert sp.simplify(h0 - jump_n) == 0
    slip = sp.Matrix([u1[0] - u2[0], u1[1] - u2[1]]).subs(z, 0)
    sigma_1tau = -t
    if region == "in":
        # Stick: no slip, |sigma_1tau|^2 = (1 - rho)^2 g_F^2 < g_F^2 where rho > 0.
        assert sp.simplify(slip) == sp.zeros(2, 1)
        assert sp.simplify(sigma_1tau.dot(sigma_1tau) - (1 - rho) ** 2 * gF**2) == 0
    else:
        # Slip: |sigma_1tau| = g_F and slip = -c sigma_1tau with c = sl / g0 >= 0.
        assert sp.simplify(sigma_1tau.dot(sigma_1tau) - gF**2) == 0
        assert sp.simplify(slip + (sl / g0) * sigma_1tau) == sp.zeros(2, 1)
print("identities hold: u = 0 on the clamped sides, shear t and sigma_zz = -p on z = 0 for both")
print("bodies, [u]_nu = h0; stick: no slip, |t| = (1 - rho) g_F; slip: |t| = g_F, slip = (sl/g0) t")

# The switch functions and their derivatives across the circle s = S: rho in C^3, sl in C^2.
v = sp.Symbol("v")
rho_v, sl_v = (1 - v / S) ** 4, s0 * ((v - S) / (sp.Rational(1, 2) - S)) ** 3
assert all(sp.simplify(sp.diff(rho_v, v, k).subs(v, S)) == 0 for k in range(4))
assert all(sp.simplify(sp.diff(sl_v, v, k).subs(v, S)) == 0 for k in range(3))
# g_F = |m| >= g0 on the square (m_x = g0 (1 + x/2) >= g0), the pressure in [1, 5/4].
print("rho vanishes to order 4 and sl to order 3 at the circle; g_F >= g0 = 1/4; 1 <= p <= 5/4")

tt = sp.Symbol("tt")
int_rho = sp.integrate((1 - tt / S) ** 4 * sp.pi, (tt, 0, S))
print("int rho dA =", sp.nsimplify(int_rho), "= pi S/5:", sp.simplify(int_rho - sp.pi * S / 5) == 0)
mc = m.subs({x: sp.Rational(1, 2), y: sp.Rational(1, 2)})
res_t = -mc * (1 - int_rho)
res_p = sp.integrate(sp.integrate(p, (x, 0, 1)), (y, 0, 1))
print("int p dA =", res_p, "  int sigma_1tau dA =", [sp.N(c, 17) for c in res_t])
print("r_s^2 =", sp.N(S, 20), "  r_s =", sp.N(sp.sqrt(S), 20))

fmt = lambda v: " ".join(f"{float(sp.N(c, 30)):.17g}" for c in v)
for label, point, region in [
    ("body1", (sp.Rational(2, 5), sp.Rational(11, 20), sp.Rational(1, 3)), "in"),
    ("body1", (sp.Rational(9, 10), sp.Rational(1, 5), sp.Rational(3, 4)), "out"),
    ("body2", (sp.Rational(2, 5), sp.Rational(11, 20), -sp.Rational(1, 3)), "in"),
    ("body2", (sp.Rational(9, 10), sp.Rational(1, 5), -sp.Rational(3, 4)), "out"),
]:
    u1, u2, t, rho, sl = fields(region)
    u = u1 if label == "body1" else u2
    at = dict(zip(X, point))
    sig = stress(u).subs(at)
    print(f"{label} {tuple(str(c) for c in point)} u:", fmt(u.subs(at)))
    print("  sigma xx yy zz yz xz xy:", fmt([sig[0, 0], sig[1, 1], sig[2, 2], sig[1, 2], sig[0, 2], sig[0, 1]]))
    print("  f:", fmt(force(u).subs(at)))
for point, region in [((sp.Rational(2, 5), sp.Rational(11, 20)), "in"), ((sp.Rational(9, 10), sp.Rational(1, 5)), "out")]:
    u1, u2, t, rho, sl = fields(region)
    at = {x: point[0], y: point[1], z: 0}
    slip = [(u1[k] - u2[k]).subs(at) for k in range(2)]
    print(f"Gamma_C {point}: sigma_1tau slip g_F sigma_nu:", fmt([-t[0].subs(at), -t[1].subs(at)] + slip + [gF.subs(at), -p.subs(at)]))
