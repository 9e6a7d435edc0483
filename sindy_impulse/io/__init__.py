"""Files in and out for modal testing: hammer-test records and modal tables.

:func:`read_record` and :func:`write_record` move a :class:`Record` (an evenly sampled multi-channel
record with channel names, units, nodes, directions and the force channel) to and from:

=========  ==================  ===============================================================
suffix     package             what the file gives besides the samples
=========  ==================  ===============================================================
.uff .unv  pyuff (``io``)      UFF 58 time records, ASCII or binary: names (ID line 1), units,
                               nodes and directions, fs and t0, force (specific data type 13)
.lvm       lvm-read (``io``)   names, units (Y_Unit_Label), fs (Delta_X), t0; nodes, directions
                               and force as written by this package (header Description)
.tdms      npTDMS (``io``)     names, units (unit_string), fs (wf_increment), t0; nodes,
                               directions (properties ``node``, ``direction``) and force
.mat       scipy (h5py: v7.3)  the arrays ``data``, ``fs``, ``t0``, ``channel_names``, ``units``,
                               ``nodes``, ``directions``, ``force_channel`` (1-based), or plain
                               channel arrays
.npz       numpy               the same arrays (``force_channel`` 0-based)
.csv       numpy               names and units from the header (``name [unit]``), fs and t0
                               from a ``time`` column (else ``fs=``)
=========  ==================  ===============================================================

Where a file does not mark the force, the channel named force / hammer / excitation / F (else the one in
force units, N or lbf) is taken. :func:`write_uff55` and :func:`read_uff55` write and read a modal table
as UFF 55 complex modes. The optional packages come with ``pip install "sindy-impulse[io]"``; a reader
or writer whose package is missing raises an ImportError saying so.

Examples
--------
>>> import os, tempfile
>>> import numpy as np
>>> from sindy_impulse.io import Record, read_record, write_record
>>> t = np.arange(200) / 1000.0
>>> rec = Record(np.column_stack([np.exp(-5 * t) * np.sin(2 * np.pi * 50 * t), t < 0.002]), fs=1000.0,
...              channel_names=("acc", "hammer"), units=("m/s^2", "N"))
>>> rec.force_channel is None  # a Record is what it is told; the readers find the force
True
>>> with tempfile.TemporaryDirectory() as folder:
...     back = read_record(write_record(rec, os.path.join(folder, "tap.csv")))
>>> back.force_channel, back.units, np.array_equal(back.data, rec.data)
(1, ('m/s^2', 'N'), True)
"""

# the per-format writers take a temporary path (write_record makes the write atomic): not exported
from ._arrays import read_mat, read_npz
from ._csv import read_csv
from ._dispatch import FORMATS, read_record, write_record
from ._lvm import read_lvm
from ._record import Record
from ._tdms import read_tdms
from ._uff55 import read_uff55, write_uff55
from ._uff58 import read_uff58

__all__ = [
    "FORMATS",
    "Record",
    "read_record",
    "write_record",
    "read_uff55",
    "write_uff55",
    "read_uff58",
    "read_lvm",
    "read_tdms",
    "read_mat",
    "read_npz",
    "read_csv",
]
