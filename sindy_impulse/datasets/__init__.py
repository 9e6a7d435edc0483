"""Data sets: simulated ring-downs of the paper's oscillators, synthetic hammer tests, real records.

``oscillator`` generates the paper's 1-DOF ring-downs and the noise model, ``forced`` the response of such
an oscillator to a measured random or hammer force, ``impact`` synthetic hammer-impact records of a
spring-mass chain with a known modal table; ``silverbox`` and ``flutter_rig`` load the shipped real
ring-downs (sources and licences in ``sindy_impulse/data/README.md``).
"""

from .flutter_rig import FlutterRigFreeDecay, load_flutter_rig
from .forced import ForcedResponse, forced_oscillator
from .impact import ImpactRecord, impact_record
from .oscillator import MAX_SAMPLES, RingDown, add_noise, damped_oscillator
from .silverbox import SilverboxWindows, load_silverbox

__all__ = [
    "FlutterRigFreeDecay",
    "ForcedResponse",
    "MAX_SAMPLES",
    "ImpactRecord",
    "RingDown",
    "SilverboxWindows",
    "add_noise",
    "damped_oscillator",
    "forced_oscillator",
    "impact_record",
    "load_flutter_rig",
    "load_silverbox",
]
