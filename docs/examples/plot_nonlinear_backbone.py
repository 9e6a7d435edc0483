"""
The backbone of a nonlinear ring-down
=====================================

A single mode with a hardening (Duffing) spring, ``y'' + 2 zeta w y' + w^2 y + k3 y^3 = 0``: its frequency
rises with amplitude. The survey identifies the mode's equation, cubic term included, the test for
nonlinearity calls it nonlinear, and the model's backbone (frequency against amplitude) follows the true
one, which :func:`~sindy_impulse.datasets.impact_record` knows exactly.
"""

import matplotlib.pyplot as plt
import numpy as np

from sindy_impulse import identify_modes, impact_record

record = impact_record(80.0, 0.01, fs=2000.0, duration=1.5, cubic_stiffness=2e4, sensor="displacement",
                       snr_db=50, random_state=1)
survey = identify_modes(record.y, fs=record.fs)
mode = survey.modes[0]
mode.model.print()
test = mode.nonlinearity
print(f"nonlinear: {test.nonlinear} (statistic {test.statistic:.3g}, threshold {test.threshold:.3g})")

# %%
# The model's backbone against the truth, over the amplitudes the decay covers:
curve = mode.backbone
true_f = np.array([record.true_backbone(a)[0] for a in curve.amplitude])
fig, ax = plt.subplots(figsize=(6, 3.5), layout="constrained")
ax.semilogx(curve.amplitude, curve.frequency_hz, label="identified model")
ax.semilogx(curve.amplitude, true_f, "--", label="truth")
ax.set_xlabel("amplitude (m)")
ax.set_ylabel("frequency (Hz)")
ax.legend()
plt.show()
