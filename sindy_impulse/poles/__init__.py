"""Poles: the frequencies and damping ratios of a record or of a model.

- :mod:`.esprit`: poles of a free decay by ESPRIT (Hankel-SVD shift invariance), the classical baseline;
- :mod:`.modal`: poles of an identified model (eigenvalues of its Jacobian at rest) as modal parameters.

Both import nothing but the package's infrastructure, so the diagnostics of a fit and the modal survey
read poles without importing the analyses built on fitted models.
"""

from .esprit import EspritModes, esprit
from .modal import ModalParameters, jacobian_at_origin, modal_parameters, model_modes

__all__ = ["EspritModes", "esprit", "ModalParameters", "jacobian_at_origin", "modal_parameters",
"model_modes"]
