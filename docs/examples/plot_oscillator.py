"""
The paper's oscillator
======================

Fit.
"""

from sindy_impulse import ImpulseSINDy, damped_oscillator

t, x, _ = damped_oscillator(snr_db=30, random_state=0)
model = ImpulseSINDy().fit(x, t=t, feature_names=["x", "v"])
model.print()
