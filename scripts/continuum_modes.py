#!/usr/bin/env python3
"""Closed-form anchors for the Nishida frequencies (issue 26): the elastic continua that
the block models stand for, with the study's E and density.

* Model A: the arch ring as a curved Euler-Bernoulli beam (frame elements along the ring's
  centre line, 0.64 x 3.2 m section) clamped where the fixed springers meet the free
  voussoirs (31 of the 33 voussoirs' arc). A joint rule with the face's own second moment
  converges to it; corner points are three times as stiff in rocking.
* Model C: the wall and fill between the fixed side walls as a bar fixed at both ends
  (24 m): uniform, f = sqrt(E / rho) / (2 L), and with the arch opening taken out of the
  section (1-D bar of varying area): bounds for its longitudinal mode.

Usage: scripts/continuum_modes.py   (numpy only; prints the frequencies)
"""
import numpy as np

E, RHO = 1.4039e10, 1.88e3
SPAN, RISE, T, WIDTH, HEIGHT, LENGTH = 11.36, 4.76, 0.64, 3.2, 5.8, 24.0
R = (SPAN ** 2 / 4 + RISE ** 2) / (2 * RISE)  # intrados radius


def lowest(k, m, count):
    """Lowest generalised eigenvalues of K x = w^2 M x (M symmetric positive definite)."""
    l_inv = np.linalg.inv(np.linalg.cholesky(m))
    values, vectors = np.linalg.eigh(l_inv @ k @ l_inv.T)
    return values[:count], (l_inv.T @ vectors)[:, :count]


def arch_ring_modes(free_fraction=31 / 33, elements=300):
    half_angle = np.arcsin(SPAN / 2 / R) * free_fraction
    phi = np.linspace(-half_angle, half_angle, elements + 1)
    x, z = (R + T / 2) * np.sin(phi), (R + T / 2) * np.cos(phi)
    area, inertia = T * WIDTH, WIDTH * T ** 3 / 12
    n = 3 * (elements + 1)
    k, m = np.zeros((n, n)), np.zeros((n, n))
    for e in range(elements):
        dx, dz = x[e + 1] - x[e], z[e + 1] - z[e]
        L = np.hypot(dx, dz)
        c, s = dx / L, dz / L
        kl, ml = np.zeros((6, 6)), np.zeros((6, 6))
        kl[np.ix_([0, 3], [0, 3])] = E * area / L * np.array([[1, -1], [-1, 1]])
        kl[np.ix_([1, 2, 4, 5], [1, 2, 4, 5])] = E * inertia / L ** 3 * np.array(
            [[12, 6 * L, -12, 6 * L], [6 * L, 4 * L * L, -6 * L, 2 * L * L],
             [-12, -6 * L, 12, -6 * L], [6 * L, 2 * L * L, -6 * L, 4 * L * L]])
        mass = RHO * area * L
        ml[np.ix_([0, 3], [0, 3])] = mass / 6 * np.array([[2, 1], [1, 2]])
        ml[np.ix_([1, 2, 4, 5], [1, 2, 4, 5])] = mass / 420 * np.array(
            [[156, 22 * L, 54, -13 * L], [22 * L, 4 * L * L, 13 * L, -3 * L * L],
             [54, 13 * L, 156, -22 * L], [-13 * L, -3 * L * L, -22 * L, 4 * L * L]])
        rot = np.array([[c, s, 0], [-s, c, 0], [0, 0, 1]])
        t = np.kron(np.eye(2), rot)
        idx = slice(3 * e, 3 * e + 6)
        k[idx, idx] += t.T @ kl @ t
        m[idx, idx] += t.T @ ml @ t
    free = slice(3, n - 3)  # both ends clamped
    values, vectors = lowest(k[free, free], m[free, free], 2)
    out = []
    for value, vector in zip(values, vectors.T):
        middle = 3 * (elements // 2 - 1)  # the crown node among the free dofs
        kind = "in plane, antisymmetric (x)" if abs(vector[middle]) > abs(vector[middle + 1]) else "symmetric (z)"
        out.append((np.sqrt(value) / (2 * np.pi), kind))
    return out


def bar_mode(with_opening, elements=1200):
    x = np.linspace(-LENGTH / 2, LENGTH / 2, elements + 1)
    mid, h = 0.5 * (x[1:] + x[:-1]), LENGTH / elements
    area = np.full(elements, HEIGHT)
    if with_opening:
        inside = np.abs(mid) < SPAN / 2
        area[inside] -= np.sqrt(R ** 2 - mid[inside] ** 2) - (R - RISE)
    k, m = np.zeros((elements + 1,) * 2), np.zeros((elements + 1,) * 2)
    for e in range(elements):
        k[e:e + 2, e:e + 2] += E * area[e] / h * np.array([[1, -1], [-1, 1]])
        m[e:e + 2, e:e + 2] += RHO * area[e] * h / 6 * np.array([[2, 1], [1, 2]])
    values, _ = lowest(k[1:-1, 1:-1], m[1:-1, 1:-1], 1)
    return np.sqrt(values[0]) / (2 * np.pi)


if __name__ == "__main__":
    for f, kind in arch_ring_modes():
        print(f"model A, elastic ring clamped at the fixed springers: {f:.2f} Hz, {kind}")
    print(f"model C, longitudinal mode of a 24 m bar fixed at both ends: uniform {bar_mode(False):.1f} Hz "
          f"(sqrt(E / rho) / 2L = {np.sqrt(E / RHO) / (2 * LENGTH):.1f}), with the arch opening {bar_mode(True):.1f} Hz")
