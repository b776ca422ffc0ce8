"""Records: reading and writing measured records (NumPy, CSV and text,
LabVIEW ``.lvm``, UFF data set 58), and what a record may hide (clipping, spikes)."""

from ._io import MeasuredRecord, load_record, read_record, save_record_npz, write_uff58
from ._quality import clipped_samples, clipping_warnings, despiked, spike_samples, spike_warnings
from ._quality import SPIKE_MAX_WIDTH  # not re-exported by modal: the identification spares an impact's sample
from ._units import unit_key  # not re-exported by modal: the channel tables' and campaigns' helper
from ._io import FS_CONTRADICTS, GIVE_FS  # not re-exported by modal: how a record gets its rate

__all__ = ["MeasuredRecord", "clipped_samples", "clipping_warnings", "despiked", "load_record", "read_record",
           "save_record_npz", "spike_samples", "spike_warnings", "write_uff58"]
