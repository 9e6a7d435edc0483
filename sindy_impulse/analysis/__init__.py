"""From models to answers (paper sections 3.2-3.4): complexity-error plane, consensus over repeated
impacts, parameter tracking, the test for nonlinearity and modal parameters; beyond the paper, backbone
curves (frequency and damping ratio against amplitude) of data and models, ESPRIT, a classical
modal-analysis baseline, and the Modal Assurance Criterion (MAC) between sets of mode shapes.

Imported eagerly: ``from .consensus import consensus`` binds the function, not the module of the same
name, whatever the order in which names are first used.
"""

from ..poles.esprit import EspritModes, esprit
from ..poles.modal import ModalParameters, jacobian_at_origin, modal_parameters
from .backbone import Backbone, backbone, hilbert_backbone
from .complexity import ComplexityError, complexity_error
from .consensus import Consensus, Histogram, consensus, consensus_fit
from .mac import MacResult, mac, mac_result
from .nonlinearity import NonlinearityResult, NonlinearTerm, nonlinearity_test
from .parameters import ParameterDependency, parameter_dependency

__all__ = [
    "Backbone",
    "ComplexityError",
    "Consensus",
    "EspritModes",
    "Histogram",
    "MacResult",
    "ModalParameters",
    "NonlinearTerm",
    "NonlinearityResult",
    "ParameterDependency",
    "backbone",
    "complexity_error",
    "consensus",
    "consensus_fit",
    "esprit",
    "hilbert_backbone",
    "jacobian_at_origin",
    "mac",
    "mac_result",
    "modal_parameters",
    "nonlinearity_test",
    "parameter_dependency",
]
