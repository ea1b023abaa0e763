"""Recordings and the readers of real logs, below both :mod:`gyrobench.sim` and :mod:`gyrobench.analysis`.

Modules
-------
recording
    :class:`~gyrobench.io.recording.Recording` (channels, truth, metadata) and its HDF5 and CSV
    forms.
logs
    readers of real IMU logs (EuRoC, Kalibr, ROS CSV, plain CSV) into arrays with units.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from gyrobench.base.lazy import attach

#: public name -> the submodule that defines it (imported on first access, so importing
#: this package costs nothing until a name is used)
_LAZY: dict[str, str] = {
    "Recording": "gyrobench.io.recording",
    "Channel": "gyrobench.io.recording",
    "RecordingFormatError": "gyrobench.io.recording",
    "save_hdf5": "gyrobench.io.recording",
    "load_hdf5": "gyrobench.io.recording",
    "list_hdf5": "gyrobench.io.recording",
    "to_csv": "gyrobench.io.recording",
    "HDF5StreamWriter": "gyrobench.io.recording",
    "Log": "gyrobench.io.logs",
    "read_csv_log": "gyrobench.io.logs",
}

__all__ = [
    "Recording",
    "Channel",
    "RecordingFormatError",
    "save_hdf5",
    "load_hdf5",
    "list_hdf5",
    "to_csv",
    "HDF5StreamWriter",
    "Log",
    "read_csv_log",
]

if TYPE_CHECKING:  # pragma: no cover - for type checkers and IDEs only
    from gyrobench.io.logs import Log as Log
    from gyrobench.io.logs import read_csv_log as read_csv_log
    from gyrobench.io.recording import Channel as Channel
    from gyrobench.io.recording import HDF5StreamWriter as HDF5StreamWriter
    from gyrobench.io.recording import Recording as Recording
    from gyrobench.io.recording import RecordingFormatError as RecordingFormatError
    from gyrobench.io.recording import list_hdf5 as list_hdf5
    from gyrobench.io.recording import load_hdf5 as load_hdf5
    from gyrobench.io.recording import save_hdf5 as save_hdf5
    from gyrobench.io.recording import to_csv as to_csv


__getattr__, __dir__ = attach(__name__, _LAZY)
