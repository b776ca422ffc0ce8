"""Records: reading and writing measured records (NumPy, CSV and text,
LabVIEW ``.lvm``, UFF data set 58)."""

from ._io import MeasuredRecord, load_record, read_record, save_record_npz, write_uff58

__all__ = ["MeasuredRecord", "load_record", "read_record", "save_record_npz", "write_uff58"]
