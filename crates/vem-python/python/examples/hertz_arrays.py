"""Hertz contact built from numpy arrays: an elastic indenter whose bottom is a circle of
radius R (a structured mesh of quadrilaterals written out as arrays) pressed into an elastic
block (a generated mesh), the contact pressure plotted against Hertz's.

    python crates/vem-python/python/examples/hertz_arrays.py   # shows the plot (matplotlib)
"""

import numpy as np

import vemcontact as vc

E, nu, R = 100.0, 0.3, 1.0


def indenter(nx=80, ny=20, half_width=0.8, height=1.0):
    """A quadrilateral mesh of the region above the circle of radius R through (0, 0) and
    below y = height, |x| <= half_width: its points, polygons and the parts "arc" (the
    bottom, on the circle) and "top"."""
    s = np.linspace(-half_width, half_width, nx + 1)
    t = np.linspace(0.0, 1.0, ny + 1)
    bottom = R - np.sqrt(R**2 - s**2)
    X, T = np.meshgrid(s, t)
    Y = bottom + T * (height - bottom)
    points = np.column_stack([X.ravel(), Y.ravel()])

    def v(i, j):
        return j * (nx + 1) + i

    polygons = [[v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)] for j in range(ny) for i in range(nx)]
    parts = {
        "arc": [[v(i, 0), v(i + 1, 0)] for i in range(nx)],
        "top": [[v(i, ny), v(i + 1, ny)] for i in range(nx)],
    }
    return points, polygons, parts


def solve(push=0.01):
    points, polygons, parts = indenter()
    s = vc.SceneBuilder(title="Hertz from arrays")
    top = s.add_body("indenter", vc.inline(points, polygons, parts=parts), vc.isotropic(E, nu))
    top.dirichlet("top", x=0.0, y=-push)
    block = s.add_body("block", vc.generated("quads", [[-2, -2], [2, 0]], n=100), vc.isotropic(E, nu))
    block.dirichlet("bottom", x=0.0, y=0.0)
    s.add_contact(top, "arc", other_body=block, other_part="top")
    return s.solve()


def hertz(pair):
    """Hertz's half-width and peak pressure for the load the pair carries (plane strain, two
    bodies of the same material: E* = E / (2 (1 - nu^2)))."""
    P = pair.normal_resultant
    e_star = E / (2.0 * (1.0 - nu**2))
    a = np.sqrt(4.0 * P * R / (np.pi * e_star))
    return P, a, 2.0 * P / (np.pi * a)


if __name__ == "__main__":
    result = solve()
    pair = result.pairs[0]
    P, a, p0 = hertz(pair)
    print(f"load P = {P:.5f}, Hertz a = {a:.4f}, p0 = {p0:.4f}")
    print(f"computed peak: nodal {pair.pressure.max():.4f}, consistent {pair.consistent_pressure.max():.4f}")
    import matplotlib.pyplot as plt

    x = pair.positions[:, 0]
    xs = np.linspace(-a, a, 201)
    plt.plot(x, pair.pressure, "o", ms=3, label="vemcontact, nodal pressure")
    plt.plot(x, pair.consistent_pressure, ".", label="vemcontact, consistent pressure")
    plt.plot(xs, p0 * np.sqrt(1.0 - (xs / a) ** 2), "-", label="Hertz")
    plt.xlim(-2 * a, 2 * a)
    plt.xlabel("x")
    plt.ylabel("contact pressure")
    plt.legend()
    plt.show()
