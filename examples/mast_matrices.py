"""The mass and stiffness matrices of a cantilever mast, for examples/mast_fe.toml.

A steel tube (outer diameter 76.1 mm, wall 2.9 mm, a standard structural tube size), 6.1 m tall,
clamped at the root, as 20 Euler-Bernoulli beam elements with consistent mass (Przemieniecki,
"Theory of Matrix Structural Analysis", 1968, Sect. 11.3): per element of length l, with the
element dofs (w_1, theta_1, w_2, theta_2),

    k_e = EI/l^3 [[12, 6l, -12, 6l], [6l, 4l^2, -6l, 2l^2], [-12, -6l, 12, -6l], [6l, 2l^2, -6l, 4l^2]]
    m_e = rho A l/420 [[156, 22l, 54, -13l], [22l, 4l^2, 13l, -3l^2], [54, 13l, 156, -22l],
                       [-13l, -3l^2, -22l, 4l^2]]

assembled over the nodes 1..20 (node 0, the root, is clamped: its w and theta are removed).
Dof 2(i - 1) is the lateral displacement w of node i [m], dof 2(i - 1) + 1 its rotation [rad];
the tip's w is dof 38, mid-height's (node 10) dof 18. The cantilever's closed form,
f_k = (beta_k L)^2 / (2 pi L^2) sqrt(EI / (rho A)) with beta_1 L = 1.8751 and beta_2 L = 4.6941,
gives f_1 = 2.015 Hz and f_2 = 12.63 Hz (tests/test_modal_structure.py checks the matrices'
eigenvalues against it). The beam weighs 31.9 kg; its first mode's mass at the tip is a quarter
of that, 8.0 kg, so the 36-sphere bed (149 g) is 1.9 % of it. The empty container's mass is not
in the matrices (it is light against the mast's modal mass; add it to M[38, 38] for a heavy one).

    python examples/mast_matrices.py            # writes examples/mast.npz (arrays M, K)
    python examples/mast_matrices.py OUT.npz
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

#: the tube and the mast
OUTER_DIAMETER = 0.0761      # m
WALL = 0.0029                # m
LENGTH = 6.1                 # m
ELEMENTS = 20
E = 210e9                    # Pa, steel
RHO = 7850.0                 # kg/m^3


def section():
    """(A [m^2], I [m^4]) of the tube."""
    ro = OUTER_DIAMETER / 2
    ri = ro - WALL
    return math.pi * (ro**2 - ri**2), math.pi / 4 * (ro**4 - ri**4)


def cantilever_matrices(length=LENGTH, elements=ELEMENTS):
    """(M, K) of the clamped beam, 2 * elements dofs (w, theta per free node)."""
    area, inertia = section()
    ei, rho_a = E * inertia, RHO * area
    n = 2 * (elements + 1)
    M = np.zeros((n, n))
    K = np.zeros((n, n))
    le = length / elements
    k_e = ei / le**3 * np.array([[12, 6 * le, -12, 6 * le], [6 * le, 4 * le**2, -6 * le, 2 * le**2],
                                 [-12, -6 * le, 12, -6 * le], [6 * le, 2 * le**2, -6 * le, 4 * le**2]])
    m_e = rho_a * le / 420 * np.array([[156, 22 * le, 54, -13 * le], [22 * le, 4 * le**2, 13 * le, -3 * le**2],
                                       [54, 13 * le, 156, -22 * le], [-13 * le, -3 * le**2, -22 * le, 4 * le**2]])
    for e in range(elements):
        idx = slice(2 * e, 2 * e + 4)
        K[idx, idx] += k_e
        M[idx, idx] += m_e
    # clamped root: remove node 0's w and theta
    return M[2:, 2:], K[2:, 2:]


def closed_form_frequencies(length=LENGTH):
    """f_1, f_2 [Hz] of the uniform cantilever (beta_k L = 1.8751, 4.6941)."""
    area, inertia = section()
    c = math.sqrt(E * inertia / (RHO * area))
    return tuple(b**2 / (2 * math.pi * length**2) * c for b in (1.87510407, 4.69409113))


def main(argv):
    out = Path(argv[1]) if len(argv) > 1 else Path(__file__).with_name("mast.npz")
    M, K = cantilever_matrices()
    np.savez(out, M=M, K=K)
    from scipy.linalg import eigh

    w2, phi = eigh(K, M, subset_by_index=[0, 3])
    tip, mid = 2 * ELEMENTS - 2, ELEMENTS - 2
    area, _ = section()
    print(f"wrote {out}: {M.shape[0]} dofs, beam mass {RHO * area * LENGTH:.2f} kg")
    print("closed form f1, f2 [Hz]: " + ", ".join(f"{f:.5f}" for f in closed_form_frequencies()))
    for k in range(4):
        p = phi[:, k] / phi[tip, k]
        print(f"mode {k + 1}: f = {math.sqrt(w2[k]) / (2 * math.pi):.5f} Hz, modal mass at the tip "
              f"{1 / phi[tip, k] ** 2:.4f} kg, shape at mid-height / tip {p[mid]:+.5f}")


if __name__ == "__main__":
    main(sys.argv)
