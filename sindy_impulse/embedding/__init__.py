"""Time-delay embedding (paper section 2.2): :class:`DelayEmbedding` (:mod:`.delay`) and the criteria that
choose its delay and dimension (:mod:`.criteria`: autocorrelation, auto mutual information, false nearest
neighbours, Cao's statistics)."""

from .criteria import auto_mutual_information, autocorrelation, cao_statistics, false_nearest_neighbours
from .delay import DelayEmbedding

__all__ = [
    "DelayEmbedding",
    "autocorrelation",
    "auto_mutual_information",
    "false_nearest_neighbours",
    "cao_statistics",
]
