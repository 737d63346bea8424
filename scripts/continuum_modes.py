#!/usr/bin/env python3
"""Closed-form anchors for the Nishida frequencies (issue 26): the elastic continua that
the block models stand for, with the study's E, Poisson's ratio and density.

* Model A: the arch ring as a curved beam (3-D frame elements along its centre line, a
  0.64 x 3.2 m section) clamped where the fixed springers meet the free voussoirs (31 of
  the 33 voussoirs' arc): Euler-Bernoulli, and Timoshenko (shear factor 5/6) with the
  stone's G and with a shear modulus equal to E (what K_s = K_n is to the joints). A
  joint rule with the face's own second moment converges to it in bending; corner points
  are three times as stiff in rocking.
* Model C: the wall and fill between the fixed side walls as a bar fixed at both ends
  (24 m): uniform, f = sqrt(E / rho) / (2 L), and with the arch opening taken out of the
  section (1-D bar of varying area): bounds for its longitudinal mode.

Usage: scripts/continuum_modes.py   (numpy only; prints the frequencies, about 10 s)
"""
import numpy as np

E, NU, RHO = 1.4039e10, 0.28, 1.88e3
G = E / (2 * (1 + NU))
SPAN, RISE, T, WIDTH, HEIGHT, LENGTH = 11.36, 4.76, 0.64, 3.2, 5.8, 24.0
R = (SPAN ** 2 / 4 + RISE ** 2) / (2 * RISE)  # intrados radius


def lowest(k, m, count):
    """Lowest generalised eigenpairs of K x = w^2 M x (M symmetric positive definite)."""
    l_inv = np.linalg.inv(np.linalg.cholesky(m))
    values, vectors = np.linalg.eigh(l_inv @ k @ l_inv.T)
    return values[:count], (l_inv.T @ vectors)[:, :count]


def bending(ei, length, phi):
    """Timoshenko beam bending stiffness (displacement, rotation at each end); phi = 0: Euler-Bernoulli."""
    L = length
    return ei / ((1 + phi) * L ** 3) * np.array(
        [[12, 6 * L, -12, 6 * L], [6 * L, (4 + phi) * L * L, -6 * L, (2 - phi) * L * L],
         [-12, -6 * L, 12, -6 * L], [6 * L, (2 - phi) * L * L, -6 * L, (4 + phi) * L * L]])


def bending_mass(mass, L):
    return mass / 420 * np.array([[156, 22 * L, 54, -13 * L], [22 * L, 4 * L * L, 13 * L, -3 * L * L],
                                  [54, 13 * L, 156, -22 * L], [-13 * L, -3 * L * L, -22 * L, 4 * L * L]])


def ring_modes(shear_modulus=G, timoshenko=True, free_fraction=31 / 33, elements=120, count=3):
    """(frequency in Hz, axis of the largest motion) of the lowest modes of the clamped ring."""
    area = T * WIDTH
    i_in, i_out = WIDTH * T ** 3 / 12, T * WIDTH ** 3 / 12  # bending in the ring's plane, out of it
    a, b = WIDTH / 2, T / 2
    torsion = a * b ** 3 * (16 / 3 - 3.36 * b / a * (1 - b ** 4 / (12 * a ** 4)))  # rectangle (Roark)
    half_angle = np.arcsin(SPAN / 2 / R) * free_fraction
    phi = np.linspace(-half_angle, half_angle, elements + 1)
    nodes = np.stack([(R + T / 2) * np.sin(phi), np.zeros_like(phi), (R + T / 2) * np.cos(phi)], 1)
    n = 6 * (elements + 1)
    k, m = np.zeros((n, n)), np.zeros((n, n))
    flip = np.diag([1, -1, 1, -1])  # w with the rotation about y: the sign convention of the pair
    for e in range(elements):
        chord = nodes[e + 1] - nodes[e]
        L = np.linalg.norm(chord)
        ex = chord / L
        ey = np.array([0.0, 1.0, 0.0])
        axes = np.stack([ex, ey, np.cross(ex, ey)])
        kl, ml = np.zeros((12, 12)), np.zeros((12, 12))  # local (u, v, w, rx, ry, rz) at each end
        shear_out = 12 * E * i_out / (5 / 6 * shear_modulus * area * L * L) if timoshenko else 0.0
        shear_in = 12 * E * i_in / (5 / 6 * shear_modulus * area * L * L) if timoshenko else 0.0
        kl[np.ix_([0, 6], [0, 6])] = E * area / L * np.array([[1, -1], [-1, 1]])
        kl[np.ix_([3, 9], [3, 9])] = shear_modulus * torsion / L * np.array([[1, -1], [-1, 1]])
        kl[np.ix_([1, 5, 7, 11], [1, 5, 7, 11])] = bending(E * i_out, L, shear_out)
        kl[np.ix_([2, 4, 8, 10], [2, 4, 8, 10])] = flip @ bending(E * i_in, L, shear_in) @ flip
        mass = RHO * area * L
        ml[np.ix_([0, 6], [0, 6])] = mass / 6 * np.array([[2, 1], [1, 2]])
        ml[np.ix_([3, 9], [3, 9])] = RHO * (i_in + i_out) * L / 6 * np.array([[2, 1], [1, 2]])
        ml[np.ix_([1, 5, 7, 11], [1, 5, 7, 11])] = bending_mass(mass, L)
        ml[np.ix_([2, 4, 8, 10], [2, 4, 8, 10])] = flip @ bending_mass(mass, L) @ flip
        to_global = np.kron(np.eye(4), axes)
        dofs = slice(6 * e, 6 * e + 12)
        k[dofs, dofs] += to_global.T @ kl @ to_global
        m[dofs, dofs] += to_global.T @ ml @ to_global
    free = slice(6, n - 6)  # both ends clamped
    values, vectors = lowest(k[free, free], m[free, free], count)
    out = []
    for value, vector in zip(values, vectors.T):
        motion = np.abs(vector.reshape(-1, 6)[:, :3]).sum(0)
        out.append((np.sqrt(value) / (2 * np.pi), "xyz"[int(np.argmax(motion))]))
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
    for label, modes in [("Euler-Bernoulli", ring_modes(timoshenko=False)),
                         ("Timoshenko, G = E / (2 (1 + nu))", ring_modes()),
                         ("Timoshenko, shear modulus E", ring_modes(shear_modulus=E))]:
        print(f"model A, elastic ring clamped at the fixed springers, {label}: "
              + ", ".join(f"{f:.2f} Hz ({axis})" for f, axis in modes))
    print(f"model C, longitudinal mode of a 24 m bar fixed at both ends: uniform {bar_mode(False):.1f} Hz "
          f"(sqrt(E / rho) / 2L = {np.sqrt(E / RHO) / (2 * LENGTH):.1f}), with the arch opening {bar_mode(True):.1f} Hz")
