"""A classical modal-analysis baseline: ESPRIT (Hankel-SVD shift invariance) on a free decay.

A free decay sampled every ``dt`` is a sum of damped complex exponentials ``y_k = sum_i c_i z_i**k`` with
poles ``z_i = exp(s_i dt)``. The columns of the Hankel matrix ``H[i, j] = y[i + j]`` (``L`` rows) span the
signal subspace ``[z_i**i]``, which shifted by one row is the same subspace times ``diag(z)``. ESPRIT takes
the ``order`` dominant left singular vectors ``U`` of ``H``, solves ``U[:-1] Psi = U[1:]`` by least squares
and reads the poles off the eigenvalues of ``Psi``; the amplitudes follow by least squares on the whole
record, through the normal equations, whose matrix ``V^H V`` of the poles' powers is a geometric sum in
closed form (``O(order**2)`` instead of the ``O(n order**2)`` of a QR or SVD solve).
Each oscillatory pole pair gives ``omega_n = |s|``, ``zeta = -Re(s) / |s|``.

References: R. Roy and T. Kailath, "ESPRIT - estimation of signal parameters via rotational invariance
techniques", IEEE Trans. ASSP 37(7), 1989; Y. Hua and T. K. Sarkar, "Matrix pencil method for estimating
parameters of exponentially damped/undamped sinusoids in noise", IEEE Trans. ASSP 38(5), 1990.
"""

from __future__ import annotations

from numbers import Integral, Real
from typing import NamedTuple

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view
from scipy.signal import correlate

from .._utils.params import Interval, check_param
from .._utils.powers import complex_powers
from .._utils.validation import check_signal, check_time

__all__ = ["esprit", "EspritModes", "SignalSpace", "MAX_ROWS"]

#: Most rows ``L`` of the Hankel matrix by default (``L = min(MAX_ROWS, n // 3)``).
MAX_ROWS = 512

#: Singular values below this fraction of the largest are rounding (the Gram matrix squares them).
_RELATIVE_FLOOR = 1e-7
#: A pole within the half-power band of one this many times weaker is a split of that mode.
_SPLIT_RATIO = 0.1
#: Margin above the noise edge ``median * (1 + sqrt(L / K))`` of the singular values.
_NOISE_MARGIN = 1.5


class EspritModes(NamedTuple):
    """Physical modes found by :func:`esprit`, sorted by frequency.

    Attributes
    ----------
    frequencies_hz, damped_frequencies_hz : ndarray (n_modes,)
        Undamped natural frequencies ``|s| / (2 pi)`` and damped frequencies ``Im(s) / (2 pi)``.
    damping_ratios : ndarray (n_modes,)
        ``-Re(s) / |s|``.
    amplitudes, phases : ndarray (n_modes,) or (n_modes, n_channels)
        ``y(t) ~ sum_i amplitude_i exp(-zeta_i omega_i tau) cos(omega_d,i tau + phase_i)`` with
        ``tau`` the time since the first sample.
    order : int
        Number of complex exponentials fitted (physical and discarded poles).
    noise_std : float or ndarray (n_channels,)
        Standard deviation of the residual of the fit of all poles.
    """

    frequencies_hz: np.ndarray
    damped_frequencies_hz: np.ndarray
    damping_ratios: np.ndarray
    amplitudes: np.ndarray
    phases: np.ndarray
    order: int
    noise_std: float | np.ndarray


def _hankel_gram(Y: np.ndarray, L: int) -> np.ndarray:
    """``sum_c H_c H_c^T`` for the ``L``-row Hankel matrices of the columns of ``Y``, in O(n L).

    First row by one correlation; then ``G[i+1, j+1] = G[i, j] + y[i+K] y[j+K] - y[i] y[j]``.
    """
    n = Y.shape[0]
    K = n - L + 1
    i, j = np.triu_indices(L)
    upper = np.zeros(i.size)
    for y in Y.T:
        r = correlate(y, y[:K], mode="valid")  # r[d] = sum_{k<K} y[k] y[k + d]
        pad = np.concatenate([y, np.zeros(L)])
        W0 = sliding_window_view(pad, L)[:L]  # W0[m, d] = y[m + d]
        WK = sliding_window_view(pad[K:], L)[:L]  # WK[m, d] = y[m + K + d]
        S = np.zeros((L, L))
        np.cumsum((WK[:, :1] * WK - W0[:, :1] * W0)[:-1], axis=0, out=S[1:])
        upper += r[j - i] + S[i, j - i]
    G = np.zeros((L, L))
    G[i, j] = upper
    G[j, i] = upper
    return G


def _power_gram(logz: np.ndarray, n: int, shift: np.ndarray) -> np.ndarray:
    """``V^H V`` of the poles' powers (:func:`~sindy_impulse._utils.powers.complex_powers`) in closed
    form: ``sum_k w**k`` with ``w = conj(z_i) z_j``, the geometric sum ``expm1(n a) / expm1(a)``
    (``a = log w``), scaled by the columns' shifts; ``O(order**2)`` instead of ``O(n order**2)``."""
    a = np.conj(logz)[:, None] + logz[None, :]
    sigma = shift[:, None] + shift[None, :]
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        top = np.where(sigma > 0, np.exp(n * a - sigma) - np.exp(-sigma), np.expm1(n * a))
        gram = top / np.expm1(a)
    flat = np.abs(a) < 1e-12
    gram[flat] = n * np.exp(-sigma[flat])
    return gram


#: Below this condition number of the amplitudes' Gram matrix the normal equations are solved without
#: refinement (relative error about this times the machine epsilon, 2e-12; the stabilisation diagrams of
#: the speed records have 10^1-10^5).
_NO_REFINEMENT_CONDITION = 1e4


def _least_squares(V: np.ndarray, gram: np.ndarray, Y: np.ndarray, refinements: int = 2) -> np.ndarray:
    """Least-squares ``c`` with ``V c ~ Y`` from the normal equations ``G c = V^H Y`` (``G = V^H V`` given),
    then up to ``refinements`` steps of iterative refinement on the residual, which win back the digits the
    normal equations lose (none when ``G``'s condition number is below :data:`_NO_REFINEMENT_CONDITION`:
    then they lose fewer than that many ulps). When ``G`` has an eigenvalue below ``1e-14`` of its largest
    (nearly equal poles: seen on noise-free records, never on 780 diagrams of noisy ones), the normal
    equations cannot resolve the poles' amplitudes and the SVD solve of ``V`` is used instead."""
    evals, vecs = np.linalg.eigh(gram)
    if not evals[0] > 1e-14 * evals[-1]:
        return np.linalg.lstsq(V, Y.astype(complex), rcond=None)[0]
    basis, inverse = vecs, 1.0 / evals[:, None]

    def solve(r: np.ndarray) -> np.ndarray:  # V^H r = conj(V^T conj(r))
        return basis @ ((basis.conj().T @ (V.T @ r.conj()).conj()) * inverse)

    c = solve(Y.astype(complex))
    for _ in range(refinements if evals[-1] > _NO_REFINEMENT_CONDITION * evals[0] else 0):
        c = c + solve(Y - V @ c)
    return c


def _fit_amplitudes(Y: np.ndarray, z: np.ndarray):
    """Least-squares ``c`` with ``Y[k] ~ sum_i c_i z_i**k``, the residual and each pole's energy."""
    n = Y.shape[0]
    logz = np.log(z)
    shift = np.maximum(logz.real, 0.0) * (n - 1)  # growing poles: scale columns to end at 1
    V = complex_powers(logz, n, shift)
    c = _least_squares(V, _power_gram(logz, n, shift), Y)
    resid = Y - (V @ c).real
    c = c * np.exp(-shift)[:, None]
    mod2 = np.abs(z) ** 2
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        gain = np.where(np.isclose(mod2, 1.0), n, -np.expm1(n * np.log(mod2)) / (1 - mod2))
    return c, resid, 2 * np.abs(c) ** 2 * gain[:, None]


def _band_snr_db(s: np.ndarray, energy: np.ndarray, resid: np.ndarray, dt: float) -> np.ndarray:
    """Each pole's energy over the residual's energy in its band ``f_d +- max(2 zeta f_n, 2 / T)``, in dB.

    The residual's energy between two frequencies is ``2 / n sum |R_f|**2`` over its one-sided spectrum
    (Parseval), so coloured (e.g. pink) noise is judged where the mode is.
    """
    n = resid.shape[0]
    power = np.cumsum(np.abs(np.fft.rfft(resid, axis=0)) ** 2, axis=0) * 2 / n
    freqs = np.fft.rfftfreq(n, dt)
    f_d, half = s.imag / (2 * np.pi), np.maximum(2 * np.abs(s.real) / (2 * np.pi), 2 / (n * dt))
    lo = np.clip(np.searchsorted(freqs, np.abs(f_d) - half), 1, freqs.size - 1)
    hi = np.clip(np.searchsorted(freqs, np.abs(f_d) + half, side="right") - 1, lo, freqs.size - 1)
    noise = power[hi] - power[lo - 1]
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        return 10 * np.log10(energy / np.maximum(noise, np.finfo(float).tiny))


def _physical(z, s, c, loud, duration) -> np.ndarray:
    """Indices of the physical poles sorted by frequency (see :func:`esprit`)."""
    keep = (s.imag * duration >= 2 * np.pi) & (np.abs(z) < 1) & np.any(loud, axis=1)
    keep &= np.angle(z) < np.pi * (1 - 1e-9)
    idx = np.flatnonzero(keep)
    f, half = s.imag[idx] / (2 * np.pi), -s.real[idx] / (2 * np.pi)  # half-power half-widths
    amp = np.abs(c[idx]).max(axis=1)
    overlap = np.abs(f[:, None] - f[None, :]) < half[:, None] + half[None, :]
    split = np.any(overlap & (amp[None, :] * _SPLIT_RATIO > amp[:, None]), axis=1)
    idx = idx[~split]
    return idx[np.argsort(np.abs(s[idx]))]


class SignalSpace:
    """The Hankel matrix's left singular vectors of a free decay, once, for poles at any model order.

    ``L = min(max_rows, n // 3)`` rows; the ``L x L`` Gram matrix is eigen-decomposed (see :func:`esprit`'s
    cost). :meth:`poles` at ``order`` solves the shift invariance of the first ``order`` vectors, fits the
    amplitudes and keeps the physical poles; the stabilisation diagram
    (:func:`~sindy_impulse.poles.stabilisation`) calls it at every order of its range.
    """

    def __init__(self, Y: np.ndarray, max_rows: int):
        self.Y = Y
        n = Y.shape[0]
        self.rows = max(min(max_rows, n // 3), 3)
        evals, vecs = np.linalg.eigh(_hankel_gram(Y, self.rows))
        self.singular_values = np.sqrt(np.maximum(evals[::-1], 0.0))
        self.vectors = vecs[:, ::-1]
        self._shift = np.empty((0, 0))  # U[:-1]^T U[1:] of the leading vectors (grown as orders ask)

    def default_order(self) -> int:
        """The singular values above ``1.5 x`` the noise edge (and ``1e-7`` of the largest), <= ``L // 2``."""
        sv, L, n = self.singular_values, self.rows, self.Y.shape[0]
        edge = np.median(sv) * (1 + np.sqrt(L / (n - L + 1))) * _NOISE_MARGIN
        return min(max(int(np.sum(sv > max(edge, _RELATIVE_FLOOR * sv[0]))), 1), L // 2)

    def _rotation(self, order: int) -> np.ndarray:
        """The least-squares ``Psi`` with ``U[:-1] Psi = U[1:]`` for the first ``order`` vectors ``U``.

        ``U`` has orthonormal columns, so ``U[:-1]^T U[:-1] = I - u u^T`` (``u``: its last row) and
        ``Psi = A + u (u^T A) / (1 - u^T u)`` with ``A = U[:-1]^T U[1:]`` (Sherman-Morrison); ``A`` of every
        order is a leading block of one matrix, computed once: ``O(order^2)`` a diagram order instead of
        a least-squares solve of ``L x order``. Where ``1 - u^T u`` is small the solve is used.
        """
        U = self.vectors[:, :order]
        u = U[-1]
        rest = 1.0 - float(u @ u)
        if rest < 1e-6:
            return np.linalg.lstsq(U[:-1], U[1:], rcond=None)[0]
        if self._shift.shape[0] < order:
            V = self.vectors[:, : min(max(order, 64), self.vectors.shape[1])]
            self._shift = V[:-1].T @ V[1:]
        A = self._shift[:order, :order]
        return A + np.outer(u, u @ A) / rest

    def poles(self, order: int, dt: float, min_snr_db: float):
        """``(z, s, c, residual, physical)`` at ``order``: every pole, its continuous ``s``, amplitudes, the
        fit's residual and the indices of the physical poles sorted by frequency."""
        n, L = self.Y.shape[0], self.rows
        if order > L - 2:
            raise ValueError(
                f"order={order} needs more Hankel rows: at most {L - 2} with {n} samples and max_rows"
            )
        z = np.linalg.eigvals(self._rotation(order)).astype(complex)
        z = z[np.isfinite(z) & (np.abs(z) > 1e-12)]  # a pole at 0 is a one-sample transient, not a mode
        if z.size == 0 or self.singular_values[0] == 0:
            z = np.ones(1, dtype=complex)  # fit the mean only: no physical mode
        c, resid, energy = _fit_amplitudes(self.Y, z)
        s = np.log(z) / dt
        snr_db = _band_snr_db(s, energy, resid, dt)
        return z, s, c, resid, _physical(z, s, c, snr_db >= min_snr_db, n * dt)


def _sampling_step(t, fs, n) -> float:
    if (t is None) == (fs is None):
        raise ValueError("esprit: give either t (a time step or vector) or fs (the sampling rate), not both")
    if fs is not None:
        return 1.0 / check_param("fs", fs, [Interval(Real, 0, None, "neither")], "esprit")
    dt = check_time(t, n)
    if np.ndim(dt) == 0:
        return float(dt)
    steps = np.diff(dt)
    if np.ptp(steps) > 1e-6 * np.median(steps):
        raise ValueError("t must be uniformly sampled for esprit (steps differ by more than 1e-6 relative)")
    return float(np.median(steps))


def esprit(
    y,
    t=None,
    *,
    fs: float | None = None,
    order: int | None = None,
    max_rows: int = MAX_ROWS,
    min_snr_db: float = 10.0,
    subtract_tail_mean: float | None = None,
) -> EspritModes:
    """Modal parameters of a free decay by ESPRIT (Hankel SVD and shift invariance).

    The caller passes the free decay only (from the end of the hit on; the onset is left to the caller).
    A constant offset is fitted as a real pole at ``z = 1`` and discarded, or removed beforehand with
    ``subtract_tail_mean``. Poles are kept when they are oscillatory (at least one period within the
    record, below Nyquist), stable (``|z| < 1``) and above the noise: the mode's energy over the record
    is at least ``min_snr_db`` above the energy of the fit's residual in the mode's band
    ``f_d +- max(2 zeta f_n, 2 / duration)`` (so coloured noise is judged where the mode is). A pole
    whose half-power band overlaps that of a pole ten times stronger is taken for a split of that mode
    (an over-estimated order does that) and dropped.

    **Cost.** The Hankel matrix has ``L = min(max_rows, n // 3)`` rows and all ``n - L + 1`` columns, so
    every sample is used; its ``L x L`` Gram matrix is built in ``O(n L)`` (one correlation and a running
    update along the diagonals) and eigen-decomposed instead of the SVD of the ``L x n`` matrix: about
    0.05-0.1 s for 40,000 samples with ``max_rows = 512``, growing linearly with ``n``. The Gram matrix
    squares the singular values, so components below ``1e-7`` of the strongest are treated as rounding.

    Parameters
    ----------
    y : array-like (n,) or (n, n_channels)
        The free decay; several channels share the poles (block Hankel matrix).
    t : float or array-like, optional
        Time step or uniformly spaced time vector; or give ``fs``.
    fs : float, optional
        Sampling rate (Hz).
    order : int, optional
        Number of complex exponentials fitted (2 per mode, 1 for an offset). Default: the number of
        singular values above ``1.5 x`` the noise edge ``median * (1 + sqrt(L / K))`` (and above
        ``1e-7`` of the largest), at most ``L // 2``. Coloured noise raises it (pink noise: about 90 at
        ``L = 512``), which costs time but not accuracy.
    max_rows : int
        Most Hankel rows ``L``; more rows resolve closer modes at a cost growing as ``L**2 n``.
    min_snr_db : float
        Keep a pole whose energy exceeds the residual's energy in its band by this much (in any channel).
    subtract_tail_mean : float, optional
        Fraction in (0, 0.5] of the record at its end whose mean is subtracted first.

    Returns
    -------
    EspritModes
        ``frequencies_hz``, ``damped_frequencies_hz``, ``damping_ratios``, ``amplitudes``, ``phases``
        (sorted by frequency), ``order`` and ``noise_std``.

    Examples
    --------
    >>> from sindy_impulse.datasets import impact_record
    >>> rec = impact_record([40.0, 110.0], [0.01, 0.004], fs=2000.0, duration=2.0, offset=2.0)
    >>> m = esprit(rec.y[rec.free_decay_index:], fs=rec.fs)
    >>> np.round(m.frequencies_hz, 6).tolist(), np.round(m.damping_ratios, 6).tolist()
    ([40.0, 110.0], [0.01, 0.004])
    """
    Y = check_signal(y, "y", min_samples=8)
    n = Y.shape[0]
    dt = _sampling_step(t, fs, n)
    check_param("order", order, [None, Interval(Integral, 1, None)], "esprit")
    check_param("max_rows", max_rows, [Interval(Integral, 3, None)], "esprit")
    check_param("min_snr_db", min_snr_db, [Interval(Real, None, None)], "esprit")
    check_param("subtract_tail_mean", subtract_tail_mean, [None, Interval(Real, 0, 0.5, "right")], "esprit")
    if subtract_tail_mean is not None:
        Y = Y - Y[n - max(1, int(np.ceil(subtract_tail_mean * n))) :].mean(axis=0)
    space = SignalSpace(Y, max_rows)
    order = space.default_order() if order is None else order
    z, s, c, resid, idx = space.poles(order, dt, min_snr_db)
    amps, phases = 2 * np.abs(c[idx]), np.angle(c[idx])
    noise = np.sqrt(np.sum(resid**2, axis=0) / max(n - z.size, 1))
    squeeze = (lambda a: a[..., 0]) if np.ndim(y) == 1 else (lambda a: a)
    return EspritModes(
        np.abs(s[idx]) / (2 * np.pi),
        s[idx].imag / (2 * np.pi),
        -s[idx].real / np.abs(s[idx]),
        squeeze(amps),
        squeeze(phases),
        int(order),
        float(noise[0]) if np.ndim(y) == 1 else noise,
    )
