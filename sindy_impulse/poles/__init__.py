"""Poles: the frequencies and damping ratios of a record or of a model.

- :mod:`.esprit`: poles of a free decay by ESPRIT (Hankel-SVD shift invariance), the classical baseline;
- :mod:`.stabilisation`: ESPRIT poles over a range of model orders, which of them are stable, and the
  modes the stable ones make (the stabilisation diagram);
- :mod:`.modal`: poles of an identified model (eigenvalues of its Jacobian at rest) as modal parameters.

Both import nothing but the package's infrastructure, so the diagnostics of a fit and the modal survey
read poles without importing the analyses built on fitted models.
"""

from .esprit import EspritModes, esprit
from .modal import ModalParameters, jacobian_at_origin, modal_parameters, model_modes
from .stabilisation import PoleTable, StableMode, mac_matrix, stabilisation

__all__ = [
    "mac_matrix",
    "EspritModes",
    "esprit",
    "PoleTable",
    "StableMode",
    "stabilisation",
    "ModalParameters",
    "jacobian_at_origin",
    "modal_parameters",
    "model_modes",
]
