"""From a raw hammer-test record to a modal table with one equation per mode (:func:`identify_modes`)."""

from .result import ModalSurvey, Mode, Rejected
from .survey import identify_modes

__all__ = ["ModalSurvey", "Mode", "Rejected", "identify_modes"]
