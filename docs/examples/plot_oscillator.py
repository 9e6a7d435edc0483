"""
The paper's oscillator
======================

The damped oscillator of Stender, Oberst & Hoffmann (2019), section 3.1: ``x' = v``,
``v' = -64 x - 3.2 v``, both states measured with 30 dB of noise. :class:`~sindy_impulse.ImpulseSINDy`
filters and differentiates the states, sweeps the sparsity threshold, scores every candidate by
simulating it, keeps the sparsest one that follows the data and refines its coefficients.
"""

import matplotlib.pyplot as plt

from sindy_impulse import ImpulseSINDy, damped_oscillator
from sindy_impulse.analysis import modal_parameters
from sindy_impulse.plotting import plot_reconstruction, plot_sweep

t, x, _ = damped_oscillator(snr_db=30, random_state=0)
model = ImpulseSINDy().fit(x, t=t, feature_names=["x", "v"])
model.print()

# %%
# The linear part's natural frequency and damping ratio (truth: 1.2732 Hz and 0.200), the simulation error
# Gamma of the selected model, and the verdict of its diagnostics:
print(modal_parameters(model))
print(f"Gamma = {model.gamma_:.3g}, verdict: {model.diagnostics_.verdict}")

# %%
# The threshold path: every candidate's number of terms against its simulation error. The selected model is
# the sparsest that follows the data; denser ones gain nothing but spurious terms.
fig, axes = plt.subplots(1, 3, figsize=(11, 3.2), layout="constrained")
plot_sweep(model, ax=axes[0])
plot_reconstruction(model, x, t, ax=axes[1:], state_names=["x", "v"])
plt.show()
