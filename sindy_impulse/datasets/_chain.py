"""A grounded spring-mass chain with prescribed natural frequencies and driving-point residues.

The construction solves an inverse eigenvalue problem for a Jacobi matrix (Gladwell, *Inverse Problems in
Vibration*, ch. 4):

1. The mass-normalised stiffness ``J = M^(-1/2) K M^(-1/2)`` of a chain is a Jacobi matrix (symmetric,
   tridiagonal, negative off-diagonal). Its eigenvalues are ``omega_i**2`` and the squared components of
   its unit eigenvectors at a mass ``p`` are the spectral weights ``w_i`` of that mass: the driving-point
   residues ``phi_pi**2 = w_i / m_p``. Lanczos on ``diag(omega**2)`` from the start vector ``sqrt(w)``
   gives the one Jacobi matrix with these weights at its end mass.
2. For an interior mass ``p``, the end matrix's Weyl function ``m(z) = sum w_i / (lambda_i - z)`` is split
   (``-1/m(z) = z - a - beta**2 sum c_j / (mu_j - z)``) and its poles ``mu_j`` shared between a left
   and a right sub-chain, each built by Lanczos and coupled to ``p``: same spectrum, same weights at ``p``.
3. A positive-definite Jacobi matrix is an M-matrix, so ``u = J^(-1) e_0`` is positive. The masses
   ``m = u**2`` and ``K = M^(1/2) J M^(1/2)`` give ``K 1 = e_0 k_ground``: a chain grounded at mass 0
   only (wall - k_0 - m_0 - k_1 - m_1 - ... - m_(n-1), free end), with positive springs
   ``k_(i+1) = -K[i, i+1]`` between neighbours.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["SpringMassChain", "build_chain"]


@dataclass(frozen=True, repr=False)
class SpringMassChain:
    """A grounded spring-mass chain and its modes (SI units: kg, N/m, N s/m).

    Attributes
    ----------
    masses : ndarray (n,)
        Mass ``m_i`` of each degree of freedom; mass 0 is attached to the ground.
    springs : ndarray (n,)
        ``springs[0]`` joins the ground and mass 0, ``springs[i]`` joins masses ``i - 1`` and ``i``.
    stiffness_matrix, damping_matrix : ndarray (n, n)
        ``K`` and the modal (classical) damping matrix ``C = M Phi diag(2 zeta omega) Phi^T M``.
    mode_shapes : ndarray (n, n)
        Mass-normalised mode shapes ``Phi`` (``Phi^T M Phi = I``), one column per mode, sorted by frequency.
    omega : ndarray (n,)
        Undamped natural frequencies (rad/s), exactly as requested.
    """

    masses: np.ndarray
    springs: np.ndarray
    stiffness_matrix: np.ndarray
    damping_matrix: np.ndarray
    mode_shapes: np.ndarray
    omega: np.ndarray

    def __repr__(self) -> str:
        return (
            f"SpringMassChain(n_dof={self.masses.size}, masses={np.array2string(self.masses, precision=4)}, "
            f"springs={np.array2string(self.springs, precision=4)})"
        )


def _lanczos(lam: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """The Jacobi matrix (negative off-diagonal) with eigenvalues ``lam`` and end weights ``weights``."""
    n = lam.size
    V = np.zeros((n, n))
    alpha, beta = np.zeros(n), np.zeros(max(n - 1, 0))
    V[:, 0] = np.sqrt(weights / weights.sum())
    for k in range(n):
        r = lam * V[:, k]
        alpha[k] = V[:, k] @ r
        if k == n - 1:
            break
        for _ in range(2):  # full reorthogonalisation, twice for safety
            r -= V[:, : k + 1] @ (V[:, : k + 1].T @ r)
        beta[k] = np.linalg.norm(r)
        V[:, k + 1] = r / beta[k]
    return np.diag(alpha) - np.diag(beta, 1) - np.diag(beta, -1)


def _jacobi_with_weights_at(lam: np.ndarray, weights: np.ndarray, p: int) -> np.ndarray:
    """A Jacobi matrix with eigenvalues ``lam`` whose spectral weights at row ``p`` are ``weights``."""
    n = lam.size
    T = _lanczos(lam, weights)
    if p == 0 or n == 1:
        return T
    if p == n - 1:
        return T[::-1, ::-1].copy()
    mu, vec = np.linalg.eigh(T[1:, 1:])
    c = vec[0] ** 2 * T[0, 1] ** 2  # residues of beta**2 m_1(z)
    j = np.arange(n - 1)  # spread p of the sorted poles evenly over the left sub-chain
    picks = np.floor((j + 1) * p / (n - 1)) > np.floor(j * p / (n - 1))
    left = np.zeros(n - 1, dtype=bool)
    left[np.argsort(mu)[picks]] = True
    J = np.zeros((n, n))
    J[p, p] = T[0, 0]
    for side, sl, nb in ((left, slice(0, p), p - 1), (~left, slice(p + 1, n), p + 1)):
        sub = _lanczos(mu[side], c[side])
        J[sl, sl] = sub[::-1, ::-1] if nb < p else sub
        J[p, nb] = J[nb, p] = -np.sqrt(c[side].sum())
    return J


def build_chain(omega: np.ndarray, zeta: np.ndarray, weights: np.ndarray, p: int) -> SpringMassChain:
    """The chain with natural frequencies ``omega`` whose mass ``p`` has spectral weights ``weights``.

    The masses are scaled so that ``m_p = 1``; the caller rescales (all masses, springs and dampers by
    one factor) to set the response level. ``omega`` must be sorted and distinct, ``weights`` positive.
    """
    lam = omega**2
    J = _jacobi_with_weights_at(lam, np.asarray(weights, dtype=float), p)
    u = np.linalg.solve(J, np.eye(lam.size)[:, 0])
    m = u**2 / u[p] ** 2
    sq = np.sqrt(m)
    K = sq[:, None] * J * sq[None, :]
    _, vec = np.linalg.eigh(J)
    Phi = vec / sq[:, None]
    MPhi = m[:, None] * Phi
    C = MPhi @ np.diag(2 * zeta * omega) @ MPhi.T
    springs = np.concatenate([[K.sum(axis=1)[0]], -np.diag(K, 1)])
    return SpringMassChain(m, springs, K, C, Phi, omega.copy())


def scaled(chain: SpringMassChain, factor: float) -> SpringMassChain:
    """The same chain with every mass, spring and damper multiplied by ``factor`` (same frequencies)."""
    return SpringMassChain(
        chain.masses * factor,
        chain.springs * factor,
        chain.stiffness_matrix * factor,
        chain.damping_matrix * factor,
        chain.mode_shapes / np.sqrt(factor),
        chain.omega,
    )
