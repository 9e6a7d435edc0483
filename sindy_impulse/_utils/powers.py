"""Powers of complex numbers over a sample grid, ``exp(k log z)`` for ``k = 0 .. n-1``, at a tenth of the cost
of ``n x m`` complex exponentials.

ESPRIT's amplitude fit (:mod:`sindy_impulse.poles.esprit`) and the damped-sinusoid fit of the spectral
peaks (:mod:`sindy_impulse.preprocessing.sinusoids`) evaluate every pole or component at every sample, for
records of up to 10^5 samples and tens of poles, at every iteration. Here ``exp`` runs on ``block`` rows and
on the ``n / block`` block starts only, then one complex product per value gives the rest; the relative
rounding is about ``1e-14`` for decaying poles.
"""

from __future__ import annotations

import numpy as np

__all__ = ["complex_powers"]


def complex_powers(log_z: np.ndarray, n: int, shift=None, block: int = 128, negligible=None) -> np.ndarray:
    """``exp(k log_z - shift)`` for ``k = 0 .. n - 1``, shape ``(n, m)``.

    Parameters
    ----------
    log_z : ndarray (m,) of complex
        Logarithms of the ratios from one sample to the next.
    n : int
        Number of samples.
    shift : ndarray (m,) of float, optional
        Subtracted from every exponent of its column (scales a growing column to end near 1).
    block : int
        Samples per block of directly evaluated exponentials.
    negligible : float, optional
        A block whose start decays past ``exp(-negligible)`` is zero (no subnormal numbers: they are slow).

    Returns
    -------
    ndarray (n, m) of complex

    Examples
    --------
    >>> z = np.array([0.9 * np.exp(0.3j), -0.5])
    >>> bool(np.allclose(complex_powers(np.log(z.astype(complex)), 300), z ** np.arange(300)[:, None]))
    True
    """
    log_z = np.asarray(log_z, dtype=complex)
    offset = np.zeros(log_z.size) if shift is None else np.asarray(shift, dtype=float)
    starts = np.arange(-(-n // block)) * block
    exponent = starts[:, None] * log_z[None, :] - offset[None, :]
    if negligible is not None:
        exponent = np.where(exponent.real < -negligible, -np.inf, exponent)
    head = np.exp(exponent)
    within = np.exp(np.arange(block)[:, None] * log_z[None, :])
    return (head[:, None, :] * within[None, :, :]).reshape(-1, log_z.size)[:n]
