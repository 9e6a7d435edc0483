"""From a raw hammer-test record to a modal table with one equation per mode (:func:`identify_modes`);
one table per record over many records (:func:`survey_many`)."""

from .batch import FailedRecord, survey_many
from .result import ModalSurvey, Mode, Rejected
from .survey import identify_modes

__all__ = ["FailedRecord", "ModalSurvey", "Mode", "Rejected", "identify_modes", "survey_many"]
