"""Which term of a changed mode's equation carries the change (the paper's Figure 11, on surveys).

Every coefficient of the mode's equation (:mod:`.values`: the linear stiffness ``w^2``, the linear damping
``2 zeta w``, a cubic stiffness, ...) is tested as the mode's frequency is (:mod:`.statistics`): the new
survey's coefficient against the reference surveys' (0 where a model does not have the term), Holm-corrected
over the terms. A term no reference model has and the new one has *appeared*; one every reference model
has and the new one lacks *vanished*. Each changed term is given the frequency shift (and damping-ratio
shift) it causes at the amplitude of the new survey's hit: the change of the mode's backbone
(:func:`~sindy_impulse.tracking.averaging.term_shift`) when that coefficient alone moves from the
reference's mean to the new value. The term named is the changed one with the largest shift of the
quantity that raised the alarm (frequency or damping); when no term is significant on its own, the most
significant is named and said to be so.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .averaging import backbone_at, term_shift
from .statistics import fit_scatter, holm, prediction_test
from .values import LINEAR_TERMS, term_name, term_powers

__all__ = ["TermChange", "ReferenceTerms", "changed_terms"]


@dataclass(frozen=True)
class TermChange:
    """One coefficient of a changed mode's equation against the reference.

    Attributes
    ----------
    key, name : str
        The term (``"y^3"``) and its engineering name (``"cubic stiffness"``).
    reference, reference_std : float
        The reference's mean and its test-to-test scatter (0 where no reference model has the term).
    value, std : float
        The new survey's coefficient (0 when its model lacks the term) and its ±.
    t, p : float
        The test statistic and p-value (NaN: not testable).
    significant : bool
        Changed beyond the rate asked, Holm-corrected over the mode's terms.
    status : str
        ``"appeared"``, ``"vanished"``, ``"changed"`` or ``"unchanged"``.
    frequency_shift_hz, damping_shift : float
        What the change of this coefficient alone does to the mode's frequency and damping ratio at the
        new survey's hit amplitude.
    base_frequency_hz, base_damping_ratio : float
        The mode's frequency and damping ratio at that amplitude with this coefficient at the reference's
        value (what the shifts are relative to).
    """

    key: str
    name: str
    reference: float
    reference_std: float
    value: float
    std: float
    t: float
    p: float
    significant: bool
    status: str
    frequency_shift_hz: float
    damping_shift: float
    base_frequency_hz: float = math.nan
    base_damping_ratio: float = math.nan

    @property
    def relative_frequency_shift(self) -> float:
        """``frequency_shift_hz / base_frequency_hz``."""
        return self.frequency_shift_hz / self.base_frequency_hz if self.base_frequency_hz else math.nan

    @property
    def relative_damping_shift(self) -> float:
        """``damping_shift / base_damping_ratio``."""
        return self.damping_shift / self.base_damping_ratio if self.base_damping_ratio else math.nan

    def describe(self) -> str:
        """One phrase: ``"the cubic stiffness appeared (+2.25e+03 ± 63): +0.30 % frequency at the hit"``."""
        if self.key in LINEAR_TERMS and self.reference:
            change = 100 * (self.value / self.reference - 1)
            err = 100 * self.std / abs(self.reference) if math.isfinite(self.std) else math.nan
            what = f"{change:+.3g} %" + (f" ± {err:.2g} %" if math.isfinite(err) else "")
        else:
            what = f"{self.value:+.4g}" + (f" ± {self.std:.2g}" if math.isfinite(self.std) else " (no ±)")
            if self.status == "changed":
                what += f", reference {self.reference:.4g}"
        effect = []
        powers = term_powers(self.key)
        damping = powers is not None and powers[1] % 2 == 1  # odd in y': it dissipates
        if not damping and math.isfinite(self.relative_frequency_shift) and self.frequency_shift_hz:
            effect.append(f"{100 * self.relative_frequency_shift:+.3g} % frequency")
        if damping and math.isfinite(self.relative_damping_shift) and self.damping_shift:
            effect.append(f"{100 * self.relative_damping_shift:+.3g} % damping ratio")
        verb = {"appeared": "appeared", "vanished": "vanished", "changed": "changed"}.get(
            self.status, "is unchanged"
        )
        text = f"the {self.name} {verb} ({what})"
        return text + (f": {', '.join(effect)} at the hit's amplitude" if effect and self.significant else "")


class ReferenceTerms:
    """The reference distributions of every coefficient of one mode, fitted once per term asked for."""

    def __init__(self, reference_modes: list):
        self.modes = reference_modes
        self._fits: dict = {}
        self.keys = list(dict.fromkeys(k for m in reference_modes for k in m.terms))

    def fit(self, key: str):
        """The :class:`~.statistics.Scatter` of ``key`` (0 with an unknown ± where a model lacks it)."""
        if key not in self._fits:
            x = np.array([m.terms.get(key, (0.0, math.nan))[0] for m in self.modes])
            s = np.array([m.terms.get(key, (0.0, math.nan))[1] for m in self.modes])
            proxy = np.array([10 ** (-m.snr_db / 20) for m in self.modes])
            self._fits[key] = (fit_scatter(x, s, proxy), float(np.mean([key in m.terms for m in self.modes])))
        return self._fits[key]


def _status(share_in_reference: float, in_new: bool, significant: bool) -> str:
    if not significant:
        return "unchanged"
    if share_in_reference == 0 and in_new:
        return "appeared"
    if share_in_reference == 1 and not in_new:
        return "vanished"
    return "changed"


def changed_terms(reference: ReferenceTerms, news: list, alpha: float) -> list[list[TermChange]]:
    """For each mode of ``news`` (ModeValues of new surveys), every coefficient it or the reference has,
    tested (module docstring; Holm over one mode's terms), most significant first. The reference's fits
    are shared: each term is tested for every new mode at once."""
    keys = list(dict.fromkeys(reference.keys + [k for m in news for k in m.terms]))
    absent = (0.0, math.nan)
    value = np.array([[m.terms.get(k, absent)[0] for k in keys] for m in news]).reshape(len(news), len(keys))
    std = np.array([[m.terms.get(k, absent)[1] for k in keys] for m in news]).reshape(value.shape)
    asked = np.array([[k in reference.keys or k in m.terms for k in keys] for m in news]).reshape(value.shape)
    t, p = np.full(value.shape, np.nan), np.full(value.shape, np.nan)
    proxy = np.array([10 ** (-m.snr_db / 20) for m in news])
    mean, scatter, share = np.full(len(keys), np.nan), np.full(len(keys), np.nan), np.zeros(len(keys))
    for c, key in enumerate(keys):
        ref, share[c] = reference.fit(key)
        if ref is not None:
            t[:, c], p[:, c] = prediction_test(ref, value[:, c], std[:, c], proxy)
            mean[c], scatter[c] = float(ref.mean), float(ref.std)
    p = np.where(asked, p, np.nan)
    significant = holm(p, alpha)
    out = []
    for i, new in enumerate(news):
        changes = []
        at_hit = backbone_at(new, new.amplitude)
        for c in np.flatnonzero(asked[i]):
            key, sig = keys[c], bool(significant[i, c])
            df, dz = term_shift(new, key, mean[c], new.amplitude) if math.isfinite(mean[c]) else (np.nan,) * 2
            status = _status(share[c], key in new.terms, sig)
            changes.append(TermChange(key, term_name(key), mean[c], scatter[c], value[i, c], std[i, c],
                                      t[i, c], p[i, c], sig, status, df, dz, at_hit.frequency_hz - df,
                                      at_hit.damping_ratio - dz))
        out.append(sorted(changes, key=lambda ch: np.inf if not math.isfinite(ch.p) else ch.p))
    return out


def named_term(changes: list[TermChange], quantity: str) -> tuple[TermChange | None, bool]:
    """The term that carries a change of ``quantity`` (``"frequency"`` or ``"damping"``): the significant
    one with the largest shift of it, else the most significant one; and whether it is significant."""
    shift = (
        (lambda c: abs(c.damping_shift)) if quantity == "damping" else (lambda c: abs(c.frequency_shift_hz))
    )
    significant = [c for c in changes if c.significant and math.isfinite(shift(c))]
    if significant:
        return max(significant, key=shift), True
    testable = [c for c in changes if math.isfinite(c.p)]
    return (testable[0] if testable else None), False
